#pragma once
// The contact terms of every average, one implementation: the formulas at the top of
// micro_macro.hpp added one contact at a time. The box average adds each contact once, with its
// weights over the region's volume; the kernel average adds it at every grid point of its
// kernel's reach, with the kernel's weights.
#include "micromacro/averaging/snapshot.hpp"
#include "micromacro/averaging/tensor.hpp"

namespace micromacro {

template <int dim>
struct ContactSums {
    Tensor2<dim> fabric = Tensor2<dim>::Zero();
    Tensor2<dim> stress_normal = Tensor2<dim>::Zero();
    Tensor2<dim> stress_tangential = Tensor2<dim>::Zero();
    Tensor4<dim> stiffness_normal, stiffness_tangential;

    /// Adds contact c: `w` weighs l (x) f and the stiffnesses, `w_volume` the fabric's n n (both
    /// per unit volume); a contact whose spring does not respond (`tangential_stiffness` false)
    /// is left out of C^t.
    void add(const ContactRecord<dim>& c, double w, double w_volume, bool tangential_stiffness) {
        const Vec<dim>& n = c.normal;
        fabric += w_volume * n * n.transpose();
        stress_normal += (w * c.normal_force) * c.branch * n.transpose();
        stress_tangential += w * c.branch * c.tangential_force.transpose();
        const double l2 = c.branch.squaredNorm();
        stiffness_normal.add_outer(w * c.k * l2, n, n);
        if (tangential_stiffness) stiffness_tangential.add_tangential(w * c.kt * l2, n);
    }
};

}  // namespace micromacro
