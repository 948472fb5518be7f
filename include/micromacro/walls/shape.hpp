#pragma once
// A wall's shape: the surface particles touch, seen from a particle's centre. The plane is built
// in; a scene may bring its own shape (tests/physics/wall_shapes.cpp defines a spherical bowl).
// A shape is placed by one coordinate, the offset h that its wall's motion drives: the shape at
// offset h is the shape at offset 0 translated by h along its unit direction(). A shape:
//   static constexpr std::string_view name;   recorded in state files' scene signature
//   WallPoint<dim> nearest(x, h) const;       the centre x's distance from the surface at offset
//                                             h (> 0 on the particles' side) and the surface's
//                                             unit normal there, pointing to x
//   Vec<dim> direction() const;               unit; the surface moves h' direction()
//   bool finite() const;                      its numbers are finite (a restored state's check)
//   template <class Archive> void serialize(Archive& ar);   its numbers, as ar.value(...)
// A particle touches the wall when its distance is below its radius; the contact law sees the
// wall as a partner of infinite radius and mass, with the normal given here.
#include <concepts>
#include <string_view>

#include "micromacro/core/dim_traits.hpp"

namespace micromacro {

/// Where a particle's centre stands against a wall's surface.
template <int dim>
struct WallPoint {
    double distance;  ///< signed distance of the centre from the surface, > 0 on the particles' side
    Vec<dim> normal;  ///< unit, from the surface towards the centre
};

template <class S, int dim>
concept WallShape = requires(const S& s, const Vec<dim>& x, double h) {
    { S::name } -> std::convertible_to<std::string_view>;
    { s.nearest(x, h) } -> std::same_as<WallPoint<dim>>;
    { s.direction() } -> std::convertible_to<Vec<dim>>;
    { s.finite() } -> std::convertible_to<bool>;
};

/// The plane {x : normal . x = h}, its normal pointing into the domain (the offset h is the
/// plane's distance from the origin along the normal, and moves it along the normal).
template <int dim>
struct Plane {
    static constexpr std::string_view name = "plane";
    Vec<dim> normal;  ///< unit, into the domain

    WallPoint<dim> nearest(const Vec<dim>& x, double h) const { return {normal.dot(x) - h, normal}; }
    const Vec<dim>& direction() const { return normal; }
    bool finite() const { return normal.allFinite(); }
    /// The axis this plane is perpendicular to, or -1.
    int axis() const { return aligned_axis<dim>(normal); }
    template <class Archive>
    void serialize(Archive& ar) {
        ar.value(normal);
    }
};

static_assert(WallShape<Plane<2>, 2> && WallShape<Plane<3>, 3>);

}  // namespace micromacro
