#pragma once
// BasicSimulation's integrator stages, which the integrator policies call: kick, drift and kick
// in one pass over the particles it owns (engine/particle_pass.hpp), then the walls, the clock and, when
// a particle or wall has moved far enough, the neighbour lists; and the force-change kick. The
// passes get the arrays through particle_arrays().
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "micromacro/engine/simulation.hpp"

namespace micromacro {

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::particle_arrays() -> detail::ParticleArrays<dim, Real> {
    detail::ParticleArrays<dim, Real> a{particles_.template get<field::Position>().data(),
                                        particles_.template get<field::Velocity>().data(),
                                        particles_.template get<field::Force>().data(),
                                        particles_.template get<field::InverseMass>().data(),
                                        nullptr, nullptr, nullptr, nullptr, nullptr, reference_.data(), owned_count()};
    if constexpr (rotation) {
        a.w = particles_.template get<field::AngularVelocity>().data();
        a.torque = particles_.template get<field::Torque>().data();
        a.inv_I = particles_.template get<field::InverseInertia>().data();
    }
    if constexpr (Integrator::keeps_previous_forces) {
        a.f_old = previous_force_.data();
        if constexpr (rotation) a.torque_old = previous_torque_.data();
    }
    return a;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::kick_drift_kick(double h_before, double dt, double h_after, double h_closing) -> void {
    if constexpr (Integrator::keeps_previous_forces && !std::is_same_v<Real, double>) {
        // The closing kick must round v to float before the next kick, and GCC 12 at -O2
        // folds a double -> float -> double round trip of SSE vectors to nothing (measured:
        // tests/unit/run_stages.cpp): with float storage it keeps its own pass.
        if (h_closing != 0.0) kick_force_change(h_closing);
        h_closing = 0.0;
    }
    // Without periodic axes (a box of walls, like the biaxial test) the pass skips wrapping and
    // minimum images: the same numbers, a quarter fewer instructions in the pass (2D biaxial).
    constexpr bool keep = Integrator::keeps_previous_forces;
    const auto [max_move_sq, sum_move_sq, wrap_energy] =
        domain_.any_periodic()
            ? detail::kick_drift_pass<true, rotation, keep>(particle_arrays(), domain_, h_before, dt, h_after, h_closing, active_threads())
            : detail::kick_drift_pass<false, rotation, keep>(particle_arrays(), domain_, h_before, dt, h_after, h_closing, active_threads());
    // Ghosts (set_first_ghost) are not integrated: their owners' states replace theirs before the
    // next force evaluation. Only the array that evaluation accumulates into is cleared for them.
    for (std::size_t i = owned_count(); i < particles_.size(); ++i) {
        if constexpr (keep) {
            previous_force_[i].setZero();
            if constexpr (rotation) previous_torque_[i] = zero_angular<dim, double>();
        } else {
            particles_.template get<field::Force>()[i].setZero();
            if constexpr (rotation) particles_.template get<field::Torque>()[i] = zero_angular<dim, double>();
        }
    }
    accumulators_cleared_ = true;
    if (!std::isfinite(sum_move_sq)) report_blow_up();
    if (track_energy_) books_.work_by_cell += wrap_energy;  // done at once, as the particles cross
    double wall_move = 0.0;
    if constexpr (has_walls) {
        walls_.move(time_, dt, domain_);
        for (std::size_t k = 0; k < walls_.size(); ++k)
            wall_move = std::max(wall_move, std::abs(walls_[k].offset - wall_reference_[k]));
    }
    // A moving cell deforms over the step; its images move by the change of the lattice, and a
    // pair's separation changes by at most both partners' moves and the largest such image move.
    double cell_move = 0.0;
    if (domain_.moving()) cell_move = advance_cell(dt);
    time_ += dt;
    ++steps_;
    const double move = std::sqrt(max_move_sq);
    last_move_ = move;
    if (2.0 * move + cell_move >= skin_ || move + wall_move >= skin_) rebuild_neighbors();
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::advance_cell(double dt) -> double {
    const bool rebased = domain_.advance(dt);
    if (const int k = domain_.axis_too_short(interaction_range_); k >= 0)
        throw SimulationError(detail::concat(
            "at t = ", time_ + dt, " s the cell's axis ", k, " has shrunk to ", domain_.length(k),
            ", shorter than two interaction ranges (2 x ", interaction_range_,
            "): a particle would meet two images of one partner; stop the compression earlier, or start from a larger cell "
            "(more particles)"));
    if (rebased) return std::numeric_limits<double>::infinity();  // another column for a tilt: bin again
    // |(H - H_search) n| for the images one period away in each direction: the columns' changes added.
    double move = 0.0;
    for (int k = 0; k < dim; ++k)
        if (domain_.periodic(k)) move += (domain_.lattice().col(k) - lattice_reference_.col(k)).norm();
    return move;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::kick_force_change(double h) -> void {
    static_assert(Integrator::keeps_previous_forces);
    detail::kick_force_change_pass<rotation>(particle_arrays(), h, active_threads());
}

}  // namespace micromacro
