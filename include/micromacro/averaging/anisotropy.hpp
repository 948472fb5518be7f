#pragma once
// The anisotropy of contact orientations and contact forces (Rothenburg and Bathurst 1989 in 2D;
// the tensor forms of Ouadfel and Rothenburg 2001 in 3D), over the same regions and selection
// rules as the fabric: each counted contact with weight w (micro_macro.hpp's contact_weights).
//
// With the weighted means <.> over the contacts, n the contact normal, f_n the normal force and
// f_t the tangential force vector:
//   phi      = <n n>                                 (trace 1)
//   chi^n    = <f_n n n> / <f_n>                     (trace 1)
//   chi^t    = sym <n f_t> / <f_n>                   (trace 0)
//   a^c = d(d+2)/2 dev(phi),  a^n = d(d+2)/2 dev(chi^n) - a^c,  a^t = d(d+2)/2 chi^t
// the deviatoric tensors of the second-order forms
//   E(n)   = (1 + a^c : n n) / |S^{d-1}|                   contact orientations
//   f_n(n) = <f_n> (1 + a^n : n n)                         mean normal force by orientation
//   f_t(n) = (2/d) <f_n> (a^t n - (n . a^t n) n)           mean tangential force by orientation
// exact for a distribution of that form alone (a^c for E; a^n with E isotropic; a^t likewise),
// and up to products of the coefficients otherwise (tests/physics/anisotropy.cpp gives them). In
// 2D, a tensor with eigenvalues +-a along theta and theta + pi/2 is a cos 2(n - theta) on n: the
// scalars a_c, a_n, a_t and angles theta_c, theta_n, theta_t of E = (1 + a_c cos 2(th - th_c))/2pi,
// f_n = <f_n> (1 + a_n cos 2(th - th_n)), f_t = -<f_n> a_t sin 2(th - th_t).
//
// Stress-force-fabric: where every branch vector has one length, the contact stress obeys
//   dev(sym sigma) / p = 2/(d+2) (a^c + a^n + a^t)
// exactly (q/p = (a_c + a_n + a_t)/2 in 2D, 2/5 (a^c + a^n + a^t) in 3D); unequal branches add
// their own anisotropy to it.
#include <cmath>

#include "micromacro/averaging/micro_macro.hpp"

namespace micromacro {

/// The weighted sums the anisotropy is made of, added one contact at a time (so that parts of a
/// packing add to the whole's).
template <int dim>
struct AnisotropySums {
    double weight = 0.0;                                    ///< sum of w
    double normal_force = 0.0;                              ///< sum of w f_n
    Tensor2<dim> orientation = Tensor2<dim>::Zero();        ///< sum of w n n
    Tensor2<dim> normal = Tensor2<dim>::Zero();             ///< sum of w f_n n n
    Tensor2<dim> tangential = Tensor2<dim>::Zero();         ///< sum of w n f_t

    void add(const ContactRecord<dim>& c, double w) {
        const Vec<dim>& n = c.normal;
        weight += w;
        normal_force += w * c.normal_force;
        orientation += w * n * n.transpose();
        normal += (w * c.normal_force) * n * n.transpose();
        tangential += w * n * c.tangential_force.transpose();
    }
};

template <int dim>
struct Anisotropy {
    double contacts = 0.0;            ///< weighted count of the contacts it is taken over
    double mean_normal_force = 0.0;   ///< <f_n> (N)
    Tensor2<dim> contact = Tensor2<dim>::Zero();           ///< a^c (deviatoric, symmetric)
    Tensor2<dim> normal_force = Tensor2<dim>::Zero();      ///< a^n
    Tensor2<dim> tangential_force = Tensor2<dim>::Zero();  ///< a^t
    /// Scalar magnitudes: 2D half the difference of the eigenvalues (the Fourier coefficients
    /// a_c, a_n, a_t); 3D sqrt(3/2 a : a).
    double a_c = 0.0, a_n = 0.0, a_t = 0.0;
    /// 2D: the major direction's angle from axis 1 (rad, in (-pi/2, pi/2]); 3D: 0 (principal() of
    /// a tensor gives its axes).
    double theta_c = 0.0, theta_n = 0.0, theta_t = 0.0;

    /// 2/(d+2) (a^c + a^n + a^t): dev(sigma)/p as the stress-force-fabric relation rebuilds it.
    Tensor2<dim> stress_ratio() const { return 2.0 / (dim + 2) * (contact + normal_force + tangential_force); }
};

namespace detail {
template <int dim>
double anisotropy_magnitude(const Tensor2<dim>& a) {
    if constexpr (dim == 2) return 0.5 * deviator_magnitude<2>(a);
    else return std::sqrt(1.5 * a.squaredNorm());
}
}  // namespace detail

/// The anisotropy from its sums; all zero where no contact or no normal force was counted.
template <int dim>
Anisotropy<dim> finish_anisotropy(const AnisotropySums<dim>& s) {
    Anisotropy<dim> a;
    a.contacts = s.weight;
    if (!(s.weight > 0.0) || !(s.normal_force > 0.0)) return a;
    constexpr double scale = dim * (dim + 2) / 2.0;
    a.mean_normal_force = s.normal_force / s.weight;
    a.contact = scale * deviator<dim>(s.orientation / s.weight);
    a.normal_force = scale * deviator<dim>(s.normal / s.normal_force) - a.contact;
    a.tangential_force = scale * 0.5 * (s.tangential + s.tangential.transpose()) / s.normal_force;
    a.a_c = detail::anisotropy_magnitude<dim>(a.contact);
    a.a_n = detail::anisotropy_magnitude<dim>(a.normal_force);
    a.a_t = detail::anisotropy_magnitude<dim>(a.tangential_force);
    if constexpr (dim == 2) {
        a.theta_c = major_axis_angle(a.contact);
        a.theta_n = major_axis_angle(a.normal_force);
        a.theta_t = major_axis_angle(a.tangential_force);
    }
    return a;
}

/// The anisotropy of the contacts an average over `region` counts, each with its weight of
/// l (x) f (contact-point rule: 1 inside; particle-centre rule: the inside partners' shares).
template <int dim>
Anisotropy<dim> anisotropy(const PackingSnapshot<dim>& s, const Region<dim>& region, const AveragingOptions& opt = {}) {
    const ContactWeights<dim> cw = contact_weights(s, region, opt);
    AnisotropySums<dim> sums;
    for (std::size_t q = 0; q < s.contacts.size(); ++q)
        if (cw.branch[q] != 0.0) sums.add(s.contacts[q], cw.branch[q]);
    return finish_anisotropy(sums);
}

}  // namespace micromacro
