#pragma once
// A probe of the macroscopic response: deform a static packing affinely by a small strain
// increment and measure the change of the contact stress. Every branch vector becomes
// l' = (1 - eps) l (compression positive), each contact's forces respond through its springs
// (normal: k times the overlap change; tangential: k_t times the tangential part of the branch
// change, projected into the new tangent plane and capped at the Coulomb limit if mu is given),
// and the stress is re-averaged with the deformed branches and volume. No particle relaxes, so
// to first order in eps the change is C : eps plus the geometric terms of order (f / k l) eps
// that Eq. 9 neglects.
#include <optional>

#include "micromacro/averaging/micro_macro.hpp"

namespace micromacro {

template <int dim>
struct AffineResponse {
    Tensor2<dim> stress_change;  ///< measured: sigma(eps) - sigma(0)
    Tensor2<dim> predicted;      ///< (C^n + C^t) : eps, the paper's stiffness
    /// The first-order terms Eq. 9 neglects, from the forces already carried: the turning normal
    /// and tangent plane, the stretched branch and the shrinking volume,
    ///   1/V sum w [ -f_n l (x) P eps n + (f_t . eps n) l (x) n - eps l (x) f ] + sigma tr(eps),
    /// with P = 1 - n n. predicted + geometric matches stress_change up to O(eps^2).
    Tensor2<dim> geometric;
};

/// The contacts after the affine strain `eps` (symmetric, compression positive): branches,
/// normals, overlaps and forces of the existing contacts updated, no new contacts. Positions and
/// contact points are left as they were: they only decide which contacts an average counts, and
/// an affine map keeps a point inside the mapped region exactly when it was inside the region.
template <int dim>
PackingSnapshot<dim> affinely_deformed(const PackingSnapshot<dim>& s, const Tensor2<dim>& eps,
                                       std::optional<double> mu = std::nullopt) {
    const Tensor2<dim> F = Tensor2<dim>::Identity() - eps;
    PackingSnapshot<dim> d = s;
    for (auto& c : d.contacts) {
        const Vec<dim> old_branch = c.branch;
        c.branch = F * old_branch;
        const double dist = c.branch.norm();
        c.normal = c.branch / dist;
        const double reach = c.wall ? s.radius[c.i] : s.radius[c.i] + s.radius[c.j];
        const double new_overlap = reach - dist;
        c.normal_force += c.k * (new_overlap - c.overlap);
        c.overlap = new_overlap;
        const Vec<dim> moved = c.branch - old_branch;  // relative displacement of the partners
        const Vec<dim>& n = c.normal;
        Vec<dim> ft = c.tangential_force - c.kt * (moved - n * n.dot(moved));
        ft -= n * n.dot(ft);
        if (mu && ft.norm() > *mu * std::max(c.normal_force, 0.0)) ft *= *mu * std::max(c.normal_force, 0.0) / ft.norm();
        c.tangential_force = ft;
    }
    return d;
}

/// Measured stress change of the affine probe in `region` (deformed with the packing, so its
/// volume becomes V det(1 - eps)) and the stiffness prediction C : eps of the undeformed packing.
template <int dim>
AffineResponse<dim> affine_response(const PackingSnapshot<dim>& s, const Region<dim>& region, const Tensor2<dim>& eps,
                                    const AveragingOptions& options = {}, std::optional<double> mu = std::nullopt) {
    const double volume_ratio = (Tensor2<dim>::Identity() - eps).determinant();
    const auto before = average(s, region, options);
    const auto after = average(affinely_deformed(s, eps, mu), region, options);
    Tensor2<dim> geometric = Tensor2<dim>::Zero();
    {
        const auto weights = contact_weights(s, region, options).branch;  // as average() weighs
        for (std::size_t q = 0; q < s.contacts.size(); ++q) {
            const auto& c = s.contacts[q];
            const Vec<dim> n = c.normal, en = eps * n, turn = en - n * n.dot(en);
            const Vec<dim> f = c.force();
            geometric += weights[q] * (c.branch * (-c.normal_force * turn + c.tangential_force.dot(en) * n).transpose() -
                                       (eps * c.branch) * f.transpose());
        }
        geometric /= region.volume();
        geometric += before.stress * eps.trace();
    }
    return {after.stress / volume_ratio - before.stress,
            (before.stiffness_normal + before.stiffness_tangential).contract(eps), geometric};
}

}  // namespace micromacro
