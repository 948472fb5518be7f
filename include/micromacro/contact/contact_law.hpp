#pragma once
// What the engine asks of a contact law (the ContactLawModel concept), and the built-in way to
// make one: ContactLaw, a normal model plus a tangential model held as members. A law of another
// shape (e.g. HertzMindlin, or a user's own) satisfies the concept directly; the engine never
// looks inside a law. The law's flags (`has_tangential`, `has_history`, `needs_rotation`) decide
// at compile time what a scene stores and updates.
#include <concepts>
#include <type_traits>

#include "micromacro/contact/geometry.hpp"
#include "micromacro/contact/normal.hpp"
#include "micromacro/contact/tangential.hpp"
#include "micromacro/core/inline.hpp"

namespace micromacro {

/// One evaluation of a contact: the force on i is normal.total() n + tangential.force, and the
/// tangential part acts at the contact point (its torque on i is (-a_i n) x tangential.force).
/// With energy tracking the law fills tangential.dissipated_* with what the step dissipated.
template <int dim>
struct ContactForce {
    NormalForce normal{0.0, 0.0};  ///< along n; the engine books viscous * n.v dt as dissipated
    TangentialForce<dim> tangential{};
};

/// A contact as analysis sees it, without advancing anything: forces, stored elastic energies
/// and the tangent stiffnesses that the stiffness tensors average (Sec. 3.3).
template <int dim>
struct ContactState {
    NormalForce normal{0.0, 0.0};
    Vec<dim> tangential = Vec<dim>::Zero();
    double normal_energy = 0.0;         ///< J stored in the normal spring
    double tangential_energy = 0.0;     ///< J stored in the tangential spring
    double stiffness = 0.0;             ///< d f_n / d overlap, N/m
    double tangential_stiffness = 0.0;  ///< d f_t / d (tangential displacement), N/m; 0 for a frictionless contact
    bool sliding = false;
};

/// The stiffest a contact of given effective radius and mass gets, for the stable time step:
/// stiffness (N/m) and damping coefficient (kg/s) of its normal and tangential oscillators.
struct StiffnessBound {
    double normal_stiffness, normal_damping;
    double tangential_stiffness = 0.0, tangential_damping = 0.0;
};

/// What the engine needs of a contact law in dimension `dim`:
/// - `force<track>(c, h)`: the force of one step, advancing the history h (with `track`, also
///   what it dissipated); `normal_force(c)`: the normal part alone, for a frictionless wall;
/// - `state(c, h)`: the present forces, energies and stiffnesses, advancing nothing (h null: a
///   frictionless contact, normal part only);
/// - `stiffness_bound(R*, m*)`: for the stable time step;
/// - with a history (`has_history`): `History<dim>` default-constructed is "not in contact";
///   `touched(h)`: whether the last evaluation found the contact closed; `opening_force(c, h)`:
///   a force to add at the evaluation that finds the contact open (zero if none); `step_back`
///   (undo the last advance before the same instant is evaluated again); `displace(n, d, h)`
///   (take up an imposed tangential displacement d of the contact points at a contact with
///   normal n); and `seen_from_partner(h)` found by argument-dependent lookup (the history when
///   the pair's two particles swap roles).
/// A law and its histories are plain data (numbers and fixed-size vectors, no pointers): state
/// files store them as bytes.
template <class L, int dim>
concept ContactLawIn =
    requires(const L& law, const ContactKinematics<dim>& c, typename L::template History<dim>& h,
             const typename L::template History<dim>* state_of) {
        { L::has_tangential } -> std::convertible_to<bool>;
        { L::has_history } -> std::convertible_to<bool>;
        { L::needs_rotation } -> std::convertible_to<bool>;
        { law.template force<true>(c, h) } -> std::same_as<ContactForce<dim>>;
        { law.template force<false>(c, h) } -> std::same_as<ContactForce<dim>>;
        { law.normal_force(c) } -> std::same_as<NormalForce>;
        { law.state(c, state_of) } -> std::same_as<ContactState<dim>>;
        { law.stiffness_bound(1.0, 1.0) } -> std::same_as<StiffnessBound>;
    } && std::is_trivially_copyable_v<L> && std::default_initializable<typename L::template History<dim>> &&
    (!L::has_history ||
     requires(const L& law, const ContactKinematics<dim>& c, typename L::template History<dim>& h,
              const typename L::template History<dim>& before, const Vec<dim>& u) {
         { law.touched(before) } -> std::convertible_to<bool>;
         { law.opening_force(c, before) } -> std::same_as<Vec<dim>>;
         law.step_back(u, u, 1.0, 1.0, h);
         law.displace(u, u, h);
         { seen_from_partner(before) } -> std::same_as<typename L::template History<dim>>;
     });

template <class L>
concept ContactLawModel = ContactLawIn<L, 2> && ContactLawIn<L, 3>;

template <class T>
concept TangentialModel = requires(const T& t) {
    { T::has_history } -> std::convertible_to<bool>;
    { T::needs_rotation } -> std::convertible_to<bool>;
    typename T::template History<2>;
    typename T::template History<3>;
    { t.stiffness() } -> std::convertible_to<double>;
    { t.damping() } -> std::convertible_to<double>;
};
static_assert(TangentialModel<Frictionless>);
static_assert(TangentialModel<CundallStrack>);
static_assert(TangentialModel<CundallStrackWithoutRotation>);

/// A normal model and a tangential model with constant stiffnesses (Eq. 21-29 with the built-in
/// models), as one contact law.
template <NormalModel Normal, TangentialModel Tangential = Frictionless>
struct ContactLaw {
    Normal normal;
    [[no_unique_address]] Tangential tangential{};

    static constexpr bool has_tangential = !std::is_same_v<Tangential, Frictionless>;
    static constexpr bool has_history = Tangential::has_history;
    static constexpr bool needs_rotation = Tangential::needs_rotation;
    template <int dim>
    using History = typename Tangential::template History<dim>;

    template <bool track, int dim>
    MICROMACRO_INLINE ContactForce<dim> force(const ContactKinematics<dim>& c, [[maybe_unused]] History<dim>& h) const {
        const NormalForce fn = normal.force(c.overlap, c.normal_velocity);
        if constexpr (has_tangential) {
            return {fn, tangential.template force<dim, track>(c.normal, c.relative_velocity, c.normal_velocity, fn.total(), c.overlap,
                                                              c.dt, h)};
        } else {
            return {fn};
        }
    }

    template <int dim>
    MICROMACRO_INLINE NormalForce normal_force(const ContactKinematics<dim>& c) const {
        return normal.force(c.overlap, c.normal_velocity);
    }

    /// The spring of the last evaluation, its force capped at the Coulomb limit of the contact's
    /// friction state (see CundallStrack::current_force).
    template <int dim>
    ContactState<dim> state(const ContactKinematics<dim>& c, [[maybe_unused]] const History<dim>* h) const {
        ContactState<dim> s;
        s.normal = normal.force(c.overlap, c.normal_velocity);
        s.normal_energy = normal.elastic_energy(c.overlap);
        s.stiffness = normal.stiffness();
        if constexpr (has_tangential) {
            if (!h) return s;
            s.tangential = tangential.current_force(c.normal, c.relative_velocity, s.normal.total(), *h);
            s.tangential_energy = tangential.elastic_energy(tangential.present_spring(c.normal, *h));
            s.tangential_stiffness = tangential.stiffness();
            s.sliding = h->sliding;
        }
        return s;
    }

    StiffnessBound stiffness_bound(double /*effective_radius*/, double /*effective_mass*/) const {
        return {normal.stiffness(), normal.damping(), tangential.stiffness(), tangential.damping()};
    }

    template <int dim>
    bool touched(const History<dim>& h) const {
        return h.touching;
    }

    /// The force that completes a just-opened contact's last evaluation (see
    /// CundallStrack::opening_correction), from the overlap and separation speed of now: the
    /// overlap then was overlap + speed dt, the normal force then the law's at that overlap, and
    /// the contact opened overlap-then / speed after it.
    template <int dim>
    Vec<dim> opening_force(const ContactKinematics<dim>& c, const History<dim>& h) const {
        if (!(c.normal_velocity > 0.0)) return Vec<dim>::Zero();
        const double overlap_then = c.overlap + c.normal_velocity * c.dt;
        if (!(overlap_then > 0.0)) return Vec<dim>::Zero();
        const double fn = normal.force(overlap_then, c.normal_velocity).total();
        return tangential.opening_correction(c.normal, h, fn, overlap_then / c.normal_velocity, c.dt);
    }

    template <int dim>
    void step_back(const Vec<dim>& n, const Vec<dim>& relative_velocity, double dt_last, double dt_next, History<dim>& h) const {
        tangential.step_back(n, relative_velocity, dt_last, dt_next, h);
    }

    template <int dim>
    void displace(const Vec<dim>& n, const Vec<dim>& tangential_displacement, History<dim>& h) const {
        tangential.displace(n, tangential_displacement, h);
    }
};

/// The paper's law without friction: linear spring-dashpot only.
using FrictionlessLinear = ContactLaw<LinearSpringDashpot, Frictionless>;
/// The paper's law: linear spring-dashpot plus the Cundall-Strack spring of Eq. 23-29.
using FrictionalLinear = ContactLaw<LinearSpringDashpot, CundallStrack>;
/// The same on particles that do not rotate (rotation suppressed).
using FrictionalLinearWithoutRotation = ContactLaw<LinearSpringDashpot, CundallStrackWithoutRotation>;

static_assert(ContactLawModel<FrictionlessLinear>);
static_assert(ContactLawModel<FrictionalLinear>);
static_assert(ContactLawModel<FrictionalLinearWithoutRotation>);

}  // namespace micromacro
