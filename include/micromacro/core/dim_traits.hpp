#pragma once
// Everything that depends on the spatial dimension lives here and nowhere else.
//
// 2D scenes use the plane (x0, x1) = the paper's (x, z); rotation happens about the out-of-plane
// axis, so angular velocity, torque and rotation angle are scalars. 3D scenes use (x, y, z) and
// 3-vectors for the rotational quantities.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross product
#include <cmath>
#include <concepts>
#include <type_traits>
#include <numbers>

namespace micromacro {

template <int dim>
concept SupportedDimension = (dim == 2 || dim == 3);

template <int dim>
    requires SupportedDimension<dim>
struct DimTraits;

template <>
struct DimTraits<2> {
    static constexpr int dim = 2;
    static constexpr int rotational_dofs = 1;
    static constexpr int voigt_size = 3;
    static constexpr int cell_stencil = 9;  // 3^dim neighbouring cells, own cell included
    using Vec = Eigen::Vector2d;
    using Angular = double;  // angular velocity, torque: about the out-of-plane axis

    /// "Volume" of a particle of radius a: in 2D its area, as the paper's averages use.
    static double particle_volume(double a) { return std::numbers::pi * a * a; }

    /// a x b, the out-of-plane component.
    static Angular cross(const Vec& a, const Vec& b) { return a.x() * b.y() - a.y() * b.x(); }
    /// v x w for an out-of-plane w: (v1 w, -v0 w).
    static Vec cross(const Vec& v, Angular w) { return Vec(v.y() * w, -v.x() * w); }
    static double squared_norm(Angular w) { return w * w; }
    static double dot(Angular a, Angular b) { return a * b; }
};

template <>
struct DimTraits<3> {
    static constexpr int dim = 3;
    static constexpr int rotational_dofs = 3;
    static constexpr int voigt_size = 6;
    static constexpr int cell_stencil = 27;
    using Vec = Eigen::Vector3d;
    using Angular = Eigen::Vector3d;

    static double particle_volume(double a) { return 4.0 / 3.0 * std::numbers::pi * a * a * a; }

    static Angular cross(const Vec& a, const Vec& b) { return a.cross(b); }
    static double squared_norm(const Angular& w) { return w.squaredNorm(); }
    static double dot(const Angular& a, const Angular& b) { return a.dot(b); }
};

/// A position, velocity or force; `Real` is the storage precision (the engine computes in
/// double and may store particle state in float, see BasicSimulation).
template <int dim, class Real = double>
using Vec = Eigen::Matrix<Real, dim, 1>;
/// Angular velocity or torque: a scalar in 2D, a 3-vector in 3D.
template <int dim, class Real = double>
using Angular = std::conditional_t<dim == 2, Real, Eigen::Matrix<Real, 3, 1>>;

/// A zero angular velocity or torque.
template <int dim, class Real = double>
Angular<dim, Real> zero_angular() {
    if constexpr (dim == 2) return Real(0);
    else return Angular<dim, Real>::Zero();
}

/// The axis a unit vector lies along (either sense), or -1: which box axis a plane with this
/// normal is perpendicular to.
template <int dim>
int aligned_axis(const Vec<dim>& unit) {
    for (int k = 0; k < dim; ++k)
        if (std::abs(std::abs(unit[k]) - 1.0) < 1e-14) return k;
    return -1;
}

/// Converts a stored value (scalar or Eigen vector) to precision `To`; free when it already is.
template <class To, class From>
decltype(auto) convert(const From& x) {
    if constexpr (std::is_arithmetic_v<From>) return static_cast<To>(x);
    else if constexpr (std::is_same_v<typename From::Scalar, To>) return (x);
    else return x.template cast<To>().eval();
}

}  // namespace micromacro
