#pragma once
// The physics of one contact as the engine applies it, shared by the pair loop, the wall loop
// and the analysis views: the law's force with its energy books, the relative velocity of the
// contact points (Eq. 25), and the view that analysis sees. Everything the engine knows of a
// law goes through the ContactLawModel concept (contact/contact_law.hpp).
#include "micromacro/contact/contact_law.hpp"
#include "micromacro/contact/geometry.hpp"
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

/// The law's force on contact `c` with history `h`; a `smooth` contact (a frictionless wall)
/// takes the normal part only.
template <bool track, int dim, class Law, class History>
MICROMACRO_INLINE ContactForce<dim> evaluate(const Law& law, const ContactKinematics<dim>& c, History& h, bool smooth) {
    if constexpr (Law::has_tangential)
        if (smooth) return {law.normal_force(c)};
    return law.template force<track>(c, h);
}

/// One evaluation of `law` on contact `c`, as the loops apply it; what it dissipates goes to
/// `books` (a local copy in the pair loop, so the sums stay in registers) times `weight` (half
/// for a pair with a ghost, which another process evaluates too).
template <bool track, int dim, class Law, class History>
MICROMACRO_INLINE ContactResponse<dim> respond(const Law& law, const ContactKinematics<dim>& c, History& h, EnergyBooks& books,
                                               bool smooth = false, double weight = 1.0) {
    const ContactForce<dim> f = evaluate<track>(law, c, h, smooth);
    const double viscous = f.normal.viscous, normal = f.normal.elastic + viscous;
    if constexpr (track) books.dissipated_normal -= weight * (viscous * c.normal_velocity * c.dt);
    ContactResponse<dim> out{normal * c.normal, Vec<dim>::Zero(), normal};
    if constexpr (Law::has_tangential) {
        if (smooth) return out;
        if constexpr (track) {
            books.dissipated_tangential += weight * f.tangential.dissipated_viscous;
            books.dissipated_sliding += weight * f.tangential.dissipated_sliding;
        }
        out.force += f.tangential.force;
        out.tangential = f.tangential.force;
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

/// A contact as analysis sees it, with the forces of the present state (see ContactLawIn::state);
/// `h` null for a frictionless contact.
template <int dim, class Law, class History>
ContactView<dim> contact_view(const Law& law, Index i, Index j, bool wall, const ContactKinematics<dim>& c, const Vec<dim>& branch,
                              const History* h) {
    const ContactState<dim> s = law.state(c, h);
    ContactView<dim> v{i, j, wall, c, branch};  // the view keeps the geometry of the kinematics
    v.normal_force = s.normal.total();
    v.normal_elastic_force = s.normal.elastic;
    v.tangential_force = s.tangential;
    v.normal_energy = s.normal_energy;
    v.tangential_energy = s.tangential_energy;
    v.stiffness = s.stiffness;
    v.tangential_stiffness = s.tangential_stiffness;
    v.sliding = s.sliding;
    return v;
}

}  // namespace micromacro::detail
