#pragma once
// An affine velocity field u(x) = u0 + L (x - x0): the mean flow of a box whose boundaries move
// (Walls::affine_field), the reference against which damping policies measure a particle's
// motion (forces/body_forces.hpp). The zero field is the lab frame.
#include "micromacro/core/dim_traits.hpp"

namespace micromacro {

template <int dim>
struct AffineField {
    using V = Vec<dim>;
    using M = Eigen::Matrix<double, dim, dim>;
    V origin = V::Zero();               ///< x0
    V velocity_at_origin = V::Zero();   ///< u0 (m/s)
    M gradient = M::Zero();             ///< L = grad u (1/s)

    V velocity(const V& x) const { return velocity_at_origin + gradient * (x - origin); }
    /// The field's angular velocity, half its vorticity: what a particle carried along rigidly
    /// by the flow turns at (zero for a pure strain such as a box stretched along its axes).
    Angular<dim> spin() const {
        if constexpr (dim == 2) return 0.5 * (gradient(1, 0) - gradient(0, 1));
        else
            return 0.5 * Vec<3>(gradient(2, 1) - gradient(1, 2), gradient(0, 2) - gradient(2, 0), gradient(1, 0) - gradient(0, 1));
    }
};

}  // namespace micromacro
