#pragma once
// BasicSimulation's state as a whole: what serialize() visits (so that a restored simulation
// continues bit for bit), the checks of a restored state, and the memory the arrays hold.
#include <string>

#include "micromacro/engine/simulation.hpp"

namespace micromacro {

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
template <class Archive>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::serialize(Archive& ar) -> void {
    // A state holds its pairs in index order (check_restored refuses others), and keys are not saved.
    if (!pair_key_.empty())
        detail::throw_input_error("a scene whose pairs go in the order of keys (set_pair_order) has no state to save or restore; "
                                  "call set_pair_order({}) first (a distributed run saves through mpi::whole_scene)");
    ar.raw(law_);  // plain parameter structs
    domain_.serialize(ar);
    if constexpr (has_walls) walls_.serialize(ar);
    std::apply([&](auto&... f) { (ar.raw(f), ...); }, body_forces_);
    particles_.serialize(ar);
    pairs_.serialize(ar);
    if constexpr (has_walls) {
        wall_contacts_.serialize(ar);
        ar.array(wall_reference_);
        ar.array(wall_books_);
    }
    ar.array(reference_);
    ar.value(lattice_reference_);
    if constexpr (Integrator::keeps_previous_forces) {
        ar.array(previous_force_);
        if constexpr (rotation) ar.array(previous_torque_);
    }
    ar.value(books_);
    ar.value(step_books_);
    ar.value(previous_step_books_);
    ar.value(initial_energy_);
    ar.value(dt_);
    ar.value(evaluated_dt_);
    ar.value(skin_);
    ar.value(time_);
    ar.value(steps_);
    ar.value(rebuilds_);
    ar.value(sorts_);
    ar.value(sorted_gap_);
    ar.value(auto_sort_);
    ar.value(prepared_);
    ar.value(allow_unstable_);
    ar.value(track_energy_);
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::check_restored(const std::string& source) const -> void {
    auto refuse = [&](auto&&... what) {
        detail::throw_input_error(source, ": the restored state does not hold together (", what..., ")");
    };
    const std::size_t n = particles_.size();
    particles_.check_restored(refuse);
    if (reference_.size() != n) refuse(reference_.size(), " neighbour-list references for ", n, " particles");
    if constexpr (Integrator::keeps_previous_forces) {
        if (previous_force_.size() != n) refuse(previous_force_.size(), " previous forces for ", n, " particles");
        if constexpr (rotation)
            if (previous_torque_.size() != n) refuse(previous_torque_.size(), " previous torques for ", n, " particles");
    }
    if (!pairs_.consistent()) refuse("contact histories and pairs of different lengths");
    for (std::size_t c = 0; c < pairs_.size(); ++c) {
        const auto [i, j] = pairs_.pairs()[c];
        if (!(i < j && j < n)) refuse("pair ", c, " names particles ", i, " and ", j, " of ", n);
    }
    if constexpr (has_walls) {
        walls_.check_restored(refuse);
        if (!wall_contacts_.consistent()) refuse("wall histories and wall contacts of different lengths");
        for (std::size_t c = 0; c < wall_contacts_.size(); ++c) {
            const auto [i, w] = wall_contacts_.pairs()[c];
            if (!(i < n && w < walls_.size())) refuse("wall contact ", c, " names particle ", i, " and wall ", w);
        }
    }
    if (!(dt_ > 0.0 && std::isfinite(dt_)) || !std::isfinite(time_) || !(evaluated_dt_ >= 0.0 && std::isfinite(evaluated_dt_)))
        refuse("time step ", dt_, ", time ", time_);
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::storage_bytes() const -> std::size_t {
    std::size_t b = particles_.size() * particles_.bytes_per_particle() + pairs_.bytes() +
                    (reference_.capacity() + window_x_.capacity()) * sizeof(SV);
    if constexpr (has_walls) b += wall_contacts_.bytes();
    b += pair_loop_.bytes();
    if constexpr (Integrator::keeps_previous_forces) {
        b += previous_force_.capacity() * sizeof(Vec<dim>);
        if constexpr (rotation) b += previous_torque_.capacity() * sizeof(Angular<dim>);
    }
    return b;
}

}  // namespace micromacro
