#pragma once
// The affine probe with relaxation (see averaging/affine_probe.hpp for the frozen one): a copy of
// the simulation is deformed, run until it rests, and averaged before and after.
#include "micromacro/averaging/micro_macro.hpp"
#include "micromacro/averaging/region.hpp"
#include "micromacro/engine/snapshot.hpp"

namespace micromacro {

template <int dim>
struct RelaxedResponse {
    Tensor2<dim> affine_change;   ///< stress change right after the affine step
    Tensor2<dim> relaxed_change;  ///< stress change after re-equilibration
    Tensor2<dim> predicted;       ///< (C^n + C^t) : eps of the undeformed packing
    /// (relaxed_change : eps) / (affine_change : eps): 1 for an affine material, below 1 when the
    /// particles' non-affine rearrangements soften the response the affine formula predicts.
    double ratio;
    std::size_t relaxation_steps;
};

/// The probe with relaxation: the simulation (a copy) is deformed affinely by the diagonal strain
/// eps (compression positive) - particles, walls, periodic box, springs - and then run at fixed
/// boundaries until its kinetic energy is below `kinetic_tolerance` of its elastic energy (at most
/// `max_steps`). Stresses are averaged in the inner region (margin as Region::inner) of the
/// deformed box. A stress- or strain-controlled wall keeps its motion policy while relaxing.
template <class Sim, int dim = Sim::dimension>
RelaxedResponse<dim> relaxed_response(Sim sim, const Tensor2<dim>& eps, double margin = 0.1,
                                      const AveragingOptions& options = {}, std::size_t max_steps = 1000000,
                                      double kinetic_tolerance = 1e-8) {
    if (!eps.isDiagonal(0.0))
        detail::throw_input_error("relaxed_response: eps must be diagonal (the deformed averaging box must stay a box)");
    sim.prepare();
    const auto s0 = take_snapshot(sim);
    const auto before = average(s0, Region<dim>::inner(s0, margin), options);
    sim.deform_affinely(Tensor2<dim>::Identity() - eps);
    const auto s1 = take_snapshot(sim);
    const auto affine = average(s1, Region<dim>::inner(s1, margin), options);
    std::size_t steps = 0;
    for (; steps < max_steps; steps += 100) {
        const auto e = sim.energy();
        if (e.kinetic() <= kinetic_tolerance * e.potential()) break;
        sim.run(100);
    }
    const auto s2 = take_snapshot(sim);
    const auto relaxed = average(s2, Region<dim>::inner(s2, margin), options);
    RelaxedResponse<dim> r;
    r.affine_change = affine.stress - before.stress;
    r.relaxed_change = relaxed.stress - before.stress;
    r.predicted = (before.stiffness_normal + before.stiffness_tangential).contract(eps);
    r.ratio = (r.relaxed_change.cwiseProduct(eps)).sum() / (r.affine_change.cwiseProduct(eps)).sum();
    r.relaxation_steps = steps;
    return r;
}

}  // namespace micromacro
