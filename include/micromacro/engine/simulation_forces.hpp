#pragma once
// BasicSimulation's force evaluation: the pair forces on the thread shares, the wall loop, the
// body forces, and the energy books of the step (the trapezoid that keeps them level with the
// state; see close_step_books).

#include "micromacro/engine/simulation.hpp"

namespace micromacro {

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::compute_forces() -> void {
    if constexpr (Integrator::keeps_previous_forces) {
        // swap, not copy: compute_forces_impl zeroes the arrays it accumulates into anyway
        previous_force_.swap(particles_.template get<field::Force>());
        if constexpr (rotation) previous_torque_.swap(particles_.template get<field::Torque>());
    }
    if (track_energy_) compute_forces_impl<true>();
    else compute_forces_impl<false>();
    evaluated_dt_ = dt_;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::particle_input() const
    -> detail::ContactLoopInput<dim, Real, History> {
    detail::ContactLoopInput<dim, Real, History> in{particles_.position().data(), particles_.velocity().data(),
                                                    particles_.radius().data(), particles_.template get<field::InverseMass>().data(),
                                                    nullptr, nullptr, nullptr};
    if constexpr (rotation) in.w = particles_.template get<field::AngularVelocity>().data();
    return in;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::contact_input(ContactList<History>& list)
    -> detail::ContactLoopInput<dim, Real, History> {
    auto in = particle_input();
    in.pair = list.pairs().data();
    if constexpr (Law::has_history) in.history = list.history_data();
    return in;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
template <bool track>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::pair_forces() -> void {
    Angular<dim>* torque = nullptr;
    if constexpr (rotation) torque = particles_.template get<field::Torque>().data();
    auto in = contact_input(pairs_);
    in.first_ghost = static_cast<Index>(owned_count());
    // The thread shares split the list by particle index: a list in another order runs on one.
    const int shares = pair_key_.empty() ? active_threads() : 1;
    pair_loop_.template run<track>(in, pairs_.size(), static_cast<Index>(particles_.size()), shares, domain_, law_, dt_,
                                   particles_.template get<field::Force>().data(), torque, step_books_);
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
template <bool track>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::compute_forces_impl() -> void {
    auto& f = particles_.template get<field::Force>();
    if (!accumulators_cleared_) {  // else kick_drift_kick() cleared them in its pass
        f.assign(particles_.size(), Vec<dim>::Zero());
        if constexpr (rotation) particles_.template get<field::Torque>().assign(particles_.size(), zero_angular<dim, double>());
    }
    accumulators_cleared_ = false;
    pair_forces<track>();
    if constexpr (has_walls) {
        Angular<dim>* torque = nullptr;
        if constexpr (rotation) torque = particles_.template get<field::Torque>().data();
        const auto in = contact_input(wall_contacts_);
        if (keeps_wall_terms_)
            detail::wall_forces<track, rotation, true>(in, wall_contacts_.size(), walls_, law_, dt_, f.data(), torque, step_books_,
                                                       wall_terms_);
        else
            detail::wall_forces<track, rotation, false>(in, wall_contacts_.size(), walls_, law_, dt_, f.data(), torque, step_books_,
                                                        wall_terms_);
    }
    if constexpr (sizeof...(BodyForces) > 0) {  // each in the scene's order, with one step
        const BodyForceStep<dim> step = body_force_step();
        std::apply([&](const auto&... bf) { (bf.template apply<track>(particles_, step_books_, step), ...); }, body_forces_);
    }
    if constexpr (track) close_step_books();
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::body_force_step() const -> BodyForceStep<dim> {
    // On the own particles (a ghost's force is its owner's), with the scene's mean flow.
    BodyForceStep<dim> step{dt_, {}, owned_count()};
    if constexpr (has_walls) step.flow = walls_.affine_field();
    else step.flow = {domain_.centre(), Vec<dim>::Zero(), domain_.velocity_gradient()};  // the cell's flow (zero at rest)
    return step;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::compute_forces_without_books() -> void {
    const EnergyBooks kept = books_;
    step_back_springs();
    compute_forces();
    books_ = kept;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::step_back_springs() -> void {
    if constexpr (Law::has_history) {
        if (!(evaluated_dt_ > 0.0)) return;  // nothing evaluated yet
        const auto [walls, wall_contacts] = wall_parts();
        detail::step_back_springs<rotation>(particle_input(), domain_, law_, pairs_, walls, wall_contacts, evaluated_dt_, dt_);
    }
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::close_step_books() -> void {
    if constexpr (has_walls) detail::book_wall_work(walls_, domain_, wall_books_, books_, counts_walls_);
    books_.add_mean(step_books_, previous_step_books_);
    previous_step_books_ = step_books_;
    step_books_ = {};
}

}  // namespace micromacro
