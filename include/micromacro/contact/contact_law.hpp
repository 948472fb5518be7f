#pragma once
// A contact law is a normal model plus a tangential model, held as members. The law's flags
// (`has_history`, `needs_rotation`) decide at compile time what a scene stores and updates.
#include <concepts>
#include <type_traits>

#include "micromacro/contact/normal.hpp"
#include "micromacro/contact/tangential.hpp"

namespace micromacro {

template <class T>
concept TangentialModel = requires(const T& t) {
    { T::has_history } -> std::convertible_to<bool>;
    { T::needs_rotation } -> std::convertible_to<bool>;
    typename T::template History<2>;
    typename T::template History<3>;
    { t.stiffness() } -> std::convertible_to<double>;
};
static_assert(TangentialModel<Frictionless>);
static_assert(TangentialModel<CundallStrack>);
static_assert(TangentialModel<CundallStrackWithoutRotation>);

template <NormalModel Normal, TangentialModel Tangential = Frictionless>
struct ContactLaw {
    Normal normal;
    [[no_unique_address]] Tangential tangential{};

    static constexpr bool has_tangential = !std::is_same_v<Tangential, Frictionless>;
    static constexpr bool has_history = Tangential::has_history;
    static constexpr bool needs_rotation = Tangential::needs_rotation;
    template <int dim>
    using History = typename Tangential::template History<dim>;
};

/// The paper's law without friction: linear spring-dashpot only.
using FrictionlessLinear = ContactLaw<LinearSpringDashpot, Frictionless>;
/// The paper's law: linear spring-dashpot plus the Cundall-Strack spring of Eq. 23-29.
using FrictionalLinear = ContactLaw<LinearSpringDashpot, CundallStrack>;
/// The same on particles that do not rotate (rotation suppressed).
using FrictionalLinearWithoutRotation = ContactLaw<LinearSpringDashpot, CundallStrackWithoutRotation>;

}  // namespace micromacro
