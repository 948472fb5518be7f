#pragma once
// The physics of one contact as the engine applies it, shared by the pair loop, the wall loop
// and the analysis views: the law's normal and tangential parts with their energy books, the
// relative velocity of the contact points (Eq. 25), the rest of a just-opened contact's impulse,
// and the view that analysis sees.
#include "micromacro/contact/normal.hpp"
#include "micromacro/contact/tangential.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/core/inline.hpp"
#include "micromacro/engine/contact_view.hpp"

namespace micromacro::detail {

template <int dim>
struct ContactResponse {
    Vec<dim> force;       ///< on i
    Vec<dim> tangential;  ///< tangential part of force, for the torques
    double normal_force;
};

/// One evaluation of `law` on a contact; what it dissipates goes to `books` (a local copy in the
/// pair loop, so the sums stay in registers). `h` is the contact's history (null without a
/// tangential law); a `smooth` contact (a frictionless wall) takes the normal part only.
template <bool track, int dim, class Law, class History>
MICROMACRO_INLINE ContactResponse<dim> respond(const Law& law, double dt, const Vec<dim>& n, double overlap, double normal_velocity,
                                               const Vec<dim>& relative_velocity, History* h, EnergyBooks& books,
                                               bool smooth = false) {
    const NormalForce fn = law.normal.force(overlap, normal_velocity);
    if constexpr (track) books.dissipated_normal -= fn.viscous * normal_velocity * dt;
    ContactResponse<dim> out{fn.total() * n, Vec<dim>::Zero(), fn.total()};
    if constexpr (Law::has_tangential) {
        if (smooth) return out;
        const auto ft = law.tangential.template force<dim, track>(n, relative_velocity, normal_velocity, fn.total(), overlap, dt, *h);
        if constexpr (track) {
            books.dissipated_tangential += ft.dissipated_viscous;
            books.dissipated_sliding += ft.dissipated_sliding;
        }
        out.force += ft.force;
        out.tangential = ft.force;
    }
    return out;
}

/// v_ij of Eq. 25: the relative velocity of the contact points, v_i - v_j + a_i n x w_i + a_j n x w_j,
/// from dv = v_i - v_j and the stored angular velocities w (unused without rotation).
template <bool rotation, int dim, class SA>
MICROMACRO_INLINE Vec<dim> contact_point_velocity(const Vec<dim>& n, const Vec<dim>& dv, [[maybe_unused]] const SA* w,
                                                  [[maybe_unused]] Index i, [[maybe_unused]] Index j,
                                                  [[maybe_unused]] double ri, [[maybe_unused]] double rj) {
    using T = DimTraits<dim>;
    if constexpr (rotation) return dv + T::cross(n, Angular<dim>(ri * convert<double>(w[i]) + rj * convert<double>(w[j])));
    else return dv;
}

/// The tangential force that completes a just-opened contact's last evaluation (see
/// CundallStrack::opening_correction), from the overlap and separation speed of now: the
/// overlap then was overlap + speed dt, the normal force then the law's at that overlap, and the
/// contact opened overlap-then / speed after it. Zero for a law without that correction.
template <int dim, class Law, class History>
Vec<dim> opening_correction(const Law& law, const History& h, const Vec<dim>& n, double overlap_now, double normal_velocity,
                            double dt) {
    if constexpr (requires { law.tangential.opening_correction(n, h, 0.0, 0.0, 0.0); }) {
        if (!(normal_velocity > 0.0)) return Vec<dim>::Zero();
        const double overlap_then = overlap_now + normal_velocity * dt;
        if (!(overlap_then > 0.0)) return Vec<dim>::Zero();
        const double fn = law.normal.force(overlap_then, normal_velocity).total();
        return law.tangential.opening_correction(n, h, fn, overlap_then / normal_velocity, dt);
    } else {
        return Vec<dim>::Zero();
    }
}

/// A contact as analysis sees it, with the forces of the present state (see
/// CundallStrack::current_force).
template <int dim, class Law, class History>
ContactView<dim> contact_view(const Law& law, Index i, Index j, bool wall, const Vec<dim>& n, double overlap,
                              const Vec<dim>& branch, const Vec<dim>& vr, [[maybe_unused]] const History* h,
                              [[maybe_unused]] bool smooth = false) {
    ContactView<dim> c{i, j, wall, {n, overlap, n.dot(vr), vr}, branch, 0, 0, Vec<dim>::Zero(), 0, false};
    const NormalForce fn = law.normal.force(overlap, c.geometry.normal_velocity);
    c.normal_force = fn.total();
    c.normal_elastic_force = fn.elastic;
    c.elastic_energy = law.normal.elastic_energy(overlap);
    if constexpr (Law::has_tangential) {
        if (smooth) return c;
        c.tangential_force = law.tangential.current_force(n, vr, fn.total(), *h);
        c.elastic_energy += law.tangential.elastic_energy(law.tangential.present_spring(n, *h));
        c.sliding = h->sliding;
    }
    return c;
}

}  // namespace micromacro::detail
