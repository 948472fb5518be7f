#pragma once
// Walls: a shape (walls/shape.hpp; the plane is built in) placed by an offset that a motion
// policy drives (walls/motion.hpp). A particle touches a wall when its centre is closer to the
// surface than its radius. The contact uses the scene's contact law with the wall as an
// infinite-mass partner, and the opposite force is summed on the wall (a wall marked
// frictionless uses only the law's normal part).
#include <cmath>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "micromacro/core/affine_field.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/walls/motion.hpp"
#include "micromacro/walls/shape.hpp"

namespace micromacro {

/// One wall: its shape (the base, so that a plane wall's `normal` reads as the wall's), where the
/// motion has put it, and the force the particles exert on it.
template <int dim, class Shape = Plane<dim>>
struct Wall : Shape {
    using V = Vec<dim>;
    double offset = 0.0;          ///< h: the shape's translation along its direction
    WallMotion motion = FixedMotion{};
    double speed = 0.0;           ///< dh/dt
    double initial_offset = 0.0;  ///< h at time 0 (Eq. 17's reference)
    V force = V::Zero();          ///< force ON the wall from the particles, last evaluation
    bool frictionless = false;    ///< use only the normal part of the contact law on this wall

    /// Where the centre x stands against the surface.
    WallPoint<dim> nearest(const V& x) const { return Shape::nearest(x, offset); }
    /// Signed distance of a point from the surface, positive on the particles' side.
    double distance(const V& x) const { return nearest(x).distance; }
    /// The velocity of every point of the surface.
    V velocity() const { return speed * Shape::direction(); }
    /// The particles' force on the wall along its direction, what its motion feels (< 0 when
    /// they push it back).
    double load() const { return force.dot(Shape::direction()); }
    /// Coordinate of an axis-aligned plane along its axis.
    double coordinate() const
        requires std::is_same_v<Shape, Plane<dim>>
    {
        return this->normal[this->axis()] > 0 ? offset : -offset;
    }
};

/// No walls: a scene without them compiles no wall code.
struct NoWalls {};

/// The walls of a scene, all of one shape (the engine's `Boundary` policy; NoWalls for none).
/// The box helpers (add_axis_aligned, add_box, affine_field, the cross-section of a
/// stress-controlled wall, deform) are for planes.
template <int dim, class Shape = Plane<dim>>
class Walls {
    static_assert(WallShape<Shape, dim>, "the wall shape does not satisfy WallShape (walls/shape.hpp)");

public:
    using V = Vec<dim>;
    using ShapeType = Shape;
    using WallType = Wall<dim, Shape>;
    static constexpr bool planes = std::is_same_v<Shape, Plane<dim>>;

    /// A wall of the given shape at offset 0, moved by `motion`.
    WallType& add(const Shape& shape, WallMotion motion = FixedMotion{}) {
        const std::string wall = "wall " + std::to_string(walls_.size()) + " (" + std::string(Shape::name) + ")";
        if (!shape.finite()) detail::throw_input_error(wall, ": its shape has a number that is not finite");
        const double length = V(shape.direction()).norm();
        if (!(std::abs(length - 1.0) <= 1e-12))
            detail::throw_input_error(wall, ": its direction has length ", length, "; a shape's direction() must be a unit vector");
        WallType w;
        static_cast<Shape&>(w) = shape;
        w.motion = motion;
        bool axis_aligned_plane = false;
        if constexpr (planes) axis_aligned_plane = w.axis() >= 0;
        detail::validate_motion(w.motion, !axis_aligned_plane);
        walls_.push_back(w);
        return walls_.back();
    }

    /// A plane through `point` with inward normal `normal` (normalised here).
    WallType& add(const V& normal, const V& point, WallMotion motion = FixedMotion{})
        requires planes
    {
        const double length = normal.norm();
        if (!(length > 0.0) || !std::isfinite(length))
            detail::throw_input_error("wall ", walls_.size(), ": normal has length ", length,
                                      "; give a finite, non-zero normal pointing into the domain");
        for (int k = 0; k < dim; ++k)
            if (!std::isfinite(point[k]))
                detail::throw_input_error("wall ", walls_.size(), ": point component ", k, " = ", point[k],
                                          " is not finite");
        WallType& w = add(Plane<dim>{normal / length}, motion);
        w.offset = w.normal.dot(point);
        w.initial_offset = w.offset;
        return w;
    }

    /// A wall perpendicular to `axis` at `coordinate`; `lower` walls face +axis, upper ones -axis.
    WallType& add_axis_aligned(int axis, bool lower, double coordinate, WallMotion motion = FixedMotion{})
        requires planes
    {
        V n = V::Zero();
        n[axis] = lower ? 1.0 : -1.0;
        V p = V::Zero();
        p[axis] = coordinate;
        return add(n, p, motion);
    }

    /// The 2 dim walls of the box [lo, hi], all fixed; index 2k is the lower wall of axis k.
    void add_box(const V& lo, const V& hi)
        requires planes
    {
        for (int k = 0; k < dim; ++k) {
            add_axis_aligned(k, true, lo[k]);
            add_axis_aligned(k, false, hi[k]);
        }
    }

    std::size_t size() const { return walls_.size(); }

    /// The box's mean flow: along every axis bounded by a lower and an upper axis-aligned plane
    /// (the first of each found), the velocity that grows linearly from the lower wall's to the
    /// upper wall's; zero along other axes, and everywhere for walls of other shapes. A packing
    /// that follows its walls affinely moves with this field.
    AffineField<dim> affine_field() const {
        AffineField<dim> field;
        if constexpr (planes)
            for (int k = 0; k < dim; ++k) {
                const WallType* lower = nullptr;
                const WallType* upper = nullptr;
                for (const auto& w : walls_) {
                    if (w.axis() != k) continue;
                    if (w.normal[k] > 0) {
                        if (!lower) lower = &w;
                    } else if (!upper) {
                        upper = &w;
                    }
                }
                if (!lower || !upper) continue;
                const double lo = lower->coordinate(), hi = upper->coordinate();
                const double u_lo = lower->speed * lower->normal[k], u_hi = upper->speed * upper->normal[k];  // along +axis
                field.origin[k] = lo;
                field.velocity_at_origin[k] = u_lo;
                if (hi > lo) field.gradient(k, k) = (u_hi - u_lo) / (hi - lo);
            }
        return field;
    }

    /// Maps every wall by the affine map x -> F x (planes map to planes); the mapped plane is the
    /// new reference of Eq. 17. Walls of other shapes are refused.
    void deform(const Eigen::Matrix<double, dim, dim>& F) {
        if constexpr (planes) {
            const Eigen::Matrix<double, dim, dim> normal_map = F.inverse().transpose();
            for (auto& w : walls_) {
                const V point = F * (w.offset * w.normal);
                w.normal = (normal_map * w.normal).normalized();
                w.offset = w.normal.dot(point);
                w.initial_offset = w.offset;
            }
        } else if (!walls_.empty()) {
            detail::throw_input_error("an affine deformation maps plane walls only, and this scene's walls are of shape '",
                                      Shape::name, "'");
        }
    }

    /// The kinetic energy 1/2 m_w v^2 of the stress-controlled walls (the others have no mass).
    double kinetic_energy() const {
        double e = 0.0;
        for (const auto& w : walls_)
            if (const auto* s = std::get_if<StressControlled>(&w.motion)) e += 0.5 * s->mass * w.speed * w.speed;
        return e;
    }

    /// Calls refuse(message parts...) for the first wall whose shape, position or speed is not
    /// finite (a restored state that must not run).
    template <class Refuse>
    void check_restored(Refuse&& refuse) const {
        for (std::size_t w = 0; w < walls_.size(); ++w)
            if (!walls_[w].finite() || !std::isfinite(walls_[w].offset) || !std::isfinite(walls_[w].speed))
                refuse("wall ", w, " has a shape, position or speed that is not finite");
    }

    template <class Archive>
    void serialize(Archive& ar) {
        std::size_t n = walls_.size();
        ar.value(n);
        walls_.resize(n);
        for (auto& w : walls_) {
            static_cast<Shape&>(w).serialize(ar);
            ar.value(w.offset);
            ar.value(w.speed);
            ar.value(w.initial_offset);
            ar.value(w.force);
            ar.value(w.frictionless);
            std::vector<char> kind;  // the motion's name, then its parameters and state
            std::visit([&](const auto& m) { kind.assign(m.name.begin(), m.name.end()); }, w.motion);
            ar.array(kind);
            w.motion = restored_motion(ar, w.motion, std::string_view(kind.data(), kind.size()),
                                       std::make_index_sequence<std::variant_size_v<WallMotion>>{});
        }
    }

    WallType& operator[](std::size_t w) { return walls_[w]; }
    const WallType& operator[](std::size_t w) const { return walls_[w]; }
    auto begin() { return walls_.begin(); }
    auto end() { return walls_.end(); }
    auto begin() const { return walls_.begin(); }
    auto end() const { return walls_.end(); }

    /// The cross-section a stress-controlled wall pushes on: its own area if given, else (an
    /// axis-aligned plane) the product of the box extents along the other axes (between opposite
    /// walls, or the periodic length).
    double area(const WallType& w, const Domain<dim>& domain) const {
        const auto& s = std::get<StressControlled>(w.motion);
        if (s.area > 0.0) return s.area;
        double area = 1.0;
        if constexpr (planes) {
            const int a = w.axis();
            for (int k = 0; k < dim; ++k) {
                if (k == a) continue;
                const WallType* lo = nullptr;
                const WallType* hi = nullptr;
                for (const auto& o : walls_)
                    if (o.axis() == k) (o.normal[k] > 0 ? lo : hi) = &o;
                if (lo && hi) area *= hi->coordinate() - lo->coordinate();
                else if (domain.periodic(k)) area *= domain.length(k);
                else
                    detail::throw_input_error("stress-controlled wall: axis ", k,
                                              " has neither two opposite walls nor periodicity, so the wall area is "
                                              "undefined; set StressControlled::area");
            }
        }
        return area;
    }

    /// Moves every wall from time t to t + dt. Stress-controlled walls use the wall force of the
    /// last evaluation.
    void move(double t, double dt, const Domain<dim>& domain) {
        for (auto& w : walls_) {
            if (auto* s = std::get_if<StrainControlled>(&w.motion))
                std::tie(w.offset, w.speed) = s->at(t + dt, w.initial_offset);
            else if (auto* p = std::get_if<StressControlled>(&w.motion))
                p->advance(area(w, domain), w.load(), dt, w.offset, w.speed);
        }
    }

private:
    // The motion named `name`, with its parameters and state visited by the archive (written from
    // `current` when saving); a name no motion has is refused.
    template <class Archive, std::size_t... k>
    static WallMotion restored_motion(Archive& ar, WallMotion& current, std::string_view name, std::index_sequence<k...>) {
        WallMotion out;
        bool found = false;
        auto try_one = [&]<class M>(M*) {
            if (found || name != M::name) return;
            found = true;
            if constexpr (std::is_empty_v<M>) out = M{};
            else out = ar.template restored<M>(current);
        };
        (try_one(static_cast<std::variant_alternative_t<k, WallMotion>*>(nullptr)), ...);
        if (!found) {
            std::string known;
            ((known += (k ? ", " : "") + std::string(std::variant_alternative_t<k, WallMotion>::name)), ...);
            detail::throw_input_error("a wall moves by '", name, "', a motion this build does not know (it knows ", known,
                                      "); the state was written by another version of micromacro or damaged");
        }
        return out;
    }

    std::vector<WallType> walls_;
};

}  // namespace micromacro
