#pragma once
// BasicSimulation seen from outside a step: its energies, the potential energy per particle, the
// contact count, and an imposed affine deformation.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "micromacro/engine/simulation.hpp"
#include "micromacro/neighbors/skin.hpp"

namespace micromacro {

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::energy() const -> EnergyState {
    // With ghosts (set_first_ghost), this process's part of the whole: its own particles, half
    // of each contact with a ghost (the ghost's owner counts the other half), the walls' kinetic
    // energy where it counts the walls.
    EnergyState e;
    const std::size_t own = owned_count();
    e.kinetic_translational = particles_.translational_kinetic_energy(own);
    e.kinetic_rotational = particles_.rotational_kinetic_energy(own);
    if constexpr (has_walls) e.kinetic_walls = counts_walls_ ? walls_.kinetic_energy() : 0.0;
    for_each_contact([&](const ContactView<dim>& c) {
        const double weight = c.wall || std::max(c.i, c.j) < own ? 1.0 : 0.5;
        e.elastic_normal += weight * c.normal_energy;
        e.elastic_tangential += weight * c.tangential_energy;
    });
    std::apply([&](const auto&... f) { ((e.gravitational += gravitational_energy(f)), ...); }, body_forces_);
    return e;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::energy_residual() const -> double {
    return micromacro::energy_residual(energy(), books_, initial_energy_);
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::potential_energy_per_particle() const -> std::vector<double> {
    std::vector<double> u(particles_.size(), 0.0);
    for_each_contact([&](const ContactView<dim>& c) {
        if (c.wall) u[c.i] += c.elastic_energy();
        else {
            u[c.i] += 0.5 * c.elastic_energy();
            u[c.j] += 0.5 * c.elastic_energy();
        }
    });
    return u;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::deform_affinely(const Eigen::Matrix<double, dim, dim>& F) -> void {
    if (!prepared_) prepare();
    const double energy_before = track_energy_ ? energy().total() : 0.0;
    const Domain<dim> deformed = domain_.deformed(F);
    // A periodic axis compressed below two interaction ranges would let a particle meet two
    // images of one partner, which the minimum image cannot tell apart: refused before anything moves.
    const double range = interaction_range(particles_.radius(), skin_);
    if (const int k = deformed.axis_too_short(range); k >= 0)
        detail::throw_input_error("the deformation leaves periodic axis ", k, " ", deformed.length(k), " long (from ",
                                  domain_.length(k), "), shorter than two interaction ranges (2 x ", range,
                                  "): a particle would meet two images of one partner; deform less, or start from a "
                                  "larger box (more particles)");
    Boundary mapped_walls = walls_;
    if constexpr (has_walls) mapped_walls.deform(F);  // first: walls it cannot map are refused before anything moves
    auto& x = particles_.template get<field::Position>();
    if constexpr (Law::has_history) {
        const auto [walls, wall_contacts] = wall_parts();
        detail::load_springs_affinely(F, particle_input(), domain_, law_, pairs_, walls, wall_contacts);
    }
    walls_ = std::move(mapped_walls);
    for (auto& p : x) {
        V moved = F * convert<double>(p);
        deformed.wrap(moved);
        p = convert<Real>(moved);
    }
    domain_ = deformed;
    rebuild_neighbors();
    compute_forces_without_books();
    if (track_energy_) books_.work_by_deformation += energy().total() - energy_before;  // done instantly, no loss
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::contact_count() const -> std::size_t {
    std::size_t count = 0;
    for_each_contact([&](const ContactView<dim>&) { ++count; });
    return count;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
template <class F>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::gravitational_energy(const F& force) const -> double {
    // Of the own particles (with ghosts, see energy()); a body force without a potential has none.
    if constexpr (requires { force.potential_energy(particles_, owned_count()); }) return force.potential_energy(particles_, owned_count());
    else return 0.0;
}

}  // namespace micromacro
