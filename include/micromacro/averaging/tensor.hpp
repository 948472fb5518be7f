#pragma once
// Rank-2 and rank-4 tensors of the averaging, with the views and invariants the paper uses.
//
// Rank-4 tensors keep all dim^4 entries (the tangential stiffness has no minor symmetry). Index
// convention of the paper's Eq. 9: C_abcd = l^2/V (k n_a n_b n_c n_d + k_t n_a t_b n_c t_d); on a
// symmetric strain increment eps the stress increment is C_abcd eps_cd.
#include <array>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "micromacro/core/dim_traits.hpp"

namespace micromacro {

template <int dim>
using Tensor2 = Eigen::Matrix<double, dim, dim>;

template <int dim>
class Tensor4 {
public:
    /// The dim^2 x dim^2 matrix with row (a, b) and column (c, d), index a * dim + b.
    using Matrix = Eigen::Matrix<double, dim * dim, dim * dim>;

    Tensor4() : m_(Matrix::Zero()) {}
    explicit Tensor4(const Matrix& m) : m_(m) {}

    double& operator()(int a, int b, int c, int d) { return m_(a * dim + b, c * dim + d); }
    double operator()(int a, int b, int c, int d) const { return m_(a * dim + b, c * dim + d); }
    const Matrix& matrix() const { return m_; }
    /// The dim^4 numbers, column-major (for sums over processes).
    double* data() { return m_.data(); }

    Tensor4& operator+=(const Tensor4& o) {
        m_ += o.m_;
        return *this;
    }
    Tensor4& operator*=(double s) {
        m_ *= s;
        return *this;
    }
    friend Tensor4 operator+(Tensor4 a, const Tensor4& b) { return a += b; }
    friend Tensor4 operator*(double s, Tensor4 a) { return a *= s; }

    /// Adds w u_a v_b u_c v_d (the shape of Eq. 9's terms).
    void add_outer(double w, const Vec<dim>& u, const Vec<dim>& v) {
        Eigen::Matrix<double, dim * dim, 1> uv;
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b) uv[a * dim + b] = u[a] * v[b];
        m_.noalias() += w * uv * uv.transpose();
    }
    /// Adds w n_a n_c (delta_bd - n_b n_d): the tangential term with the full tangential
    /// projector. In 2D it equals w n_a t_b n_c t_d exactly.
    void add_tangential(double w, const Vec<dim>& n) {
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b)
                for (int c = 0; c < dim; ++c)
                    for (int d = 0; d < dim; ++d)
                        (*this)(a, b, c, d) += w * n[a] * n[c] * ((b == d ? 1.0 : 0.0) - n[b] * n[d]);
    }

    /// C : eps, the stress increment of a strain increment.
    Tensor2<dim> contract(const Tensor2<dim>& eps) const {
        Tensor2<dim> s = Tensor2<dim>::Zero();
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b)
                for (int c = 0; c < dim; ++c)
                    for (int d = 0; d < dim; ++d) s(a, b) += (*this)(a, b, c, d) * eps(c, d);
        return s;
    }

    /// R C R^T as a rank-4 tensor: C'_abcd = R_ai R_bj R_ck R_dl C_ijkl.
    Tensor4 rotated(const Tensor2<dim>& R) const {
        Matrix RR;
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b)
                for (int i = 0; i < dim; ++i)
                    for (int j = 0; j < dim; ++j) RR(a * dim + b, i * dim + j) = R(a, i) * R(b, j);
        return Tensor4(RR * m_ * RR.transpose());
    }

    /// Kelvin (Mandel) matrix of the minor-symmetrised tensor: the map from symmetric strains to
    /// symmetric stresses in the orthonormal basis {e_aa} and {(e_ab + e_ba)/sqrt 2}; size
    /// DimTraits<dim>::voigt_size. Its eigenvalues are the eigenstiffnesses.
    using Kelvin = Eigen::Matrix<double, DimTraits<dim>::voigt_size, DimTraits<dim>::voigt_size>;
    Kelvin kelvin() const {
        const auto pairs = voigt_pairs();
        Kelvin K;
        for (int p = 0; p < DimTraits<dim>::voigt_size; ++p)
            for (int q = 0; q < DimTraits<dim>::voigt_size; ++q) {
                const auto [a, b] = pairs[p];
                const auto [c, d] = pairs[q];
                const double sym = 0.25 * ((*this)(a, b, c, d) + (*this)(b, a, c, d) + (*this)(a, b, d, c) +
                                           (*this)(b, a, d, c));
                K(p, q) = sym * (a == b ? 1.0 : std::numbers::sqrt2) * (c == d ? 1.0 : std::numbers::sqrt2);
            }
        return K;
    }
    /// Eigenvalues of the symmetric part of the Kelvin matrix, ascending.
    Eigen::Matrix<double, DimTraits<dim>::voigt_size, 1> kelvin_eigenvalues() const {
        const Kelvin K = kelvin();
        return Eigen::SelfAdjointEigenSolver<Kelvin>(0.5 * (K + K.transpose()), Eigen::EigenvaluesOnly).eigenvalues();
    }

    /// Voigt index pairs: 2D (11, 22, 12); 3D (11, 22, 33, 23, 13, 12).
    static std::array<std::array<int, 2>, DimTraits<dim>::voigt_size> voigt_pairs() {
        if constexpr (dim == 2) return {{{0, 0}, {1, 1}, {0, 1}}};
        else return {{{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}}};
    }

private:
    Matrix m_;
};

/// Deviator A - tr(A)/dim 1.
template <int dim>
Tensor2<dim> deviator(const Tensor2<dim>& A) {
    return A - A.trace() / dim * Tensor2<dim>::Identity();
}

/// Magnitude of the deviator, sqrt(dim/(dim-1) dev:dev): in 2D the difference of the two
/// eigenvalues (the paper's "deviator"), in 3D the von Mises-type generalisation.
template <int dim>
double deviator_magnitude(const Tensor2<dim>& A) {
    const Tensor2<dim> s = deviator<dim>(0.5 * (A + A.transpose()));
    return std::sqrt(dim / (dim - 1.0) * s.squaredNorm());
}

/// 2D: angle (radians, in (-pi/2, pi/2]) of the major eigendirection from axis 1 (x).
inline double major_axis_angle(const Tensor2<2>& A) {
    double phi = 0.5 * std::atan2(A(0, 1) + A(1, 0), A(0, 0) - A(1, 1));
    if (phi <= -0.5 * std::numbers::pi) phi += std::numbers::pi;
    return phi;
}

/// Eigenvalues (ascending) and eigenvectors (columns) of the symmetric part.
template <int dim>
Eigen::SelfAdjointEigenSolver<Tensor2<dim>> principal(const Tensor2<dim>& A) {
    return Eigen::SelfAdjointEigenSolver<Tensor2<dim>>(0.5 * (A + A.transpose()));
}

}  // namespace micromacro
