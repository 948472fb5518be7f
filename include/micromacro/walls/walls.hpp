#pragma once
// Planar walls. A wall is a plane n . x = h with unit normal n pointing into the domain; a
// particle touches it when its centre is closer than its radius. The contact uses the scene's
// contact law with the wall as an infinite-mass partner, and the opposite force is summed on
// the wall (a wall marked frictionless uses only the law's normal part). How the wall moves is its
// motion policy:
//   FixedMotion       never moves;
//   StrainControlled  moves by Eq. 17 (a cosine ramp of given travel and period, then stops);
//   StressControlled  obeys Eq. 18, m_w h'' = p A - F - gamma_w h', F the push of the particles.
// Motions act on the offset h along the inward normal, so "travel > 0" compresses.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "micromacro/core/affine_field.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"

namespace micromacro {

// Each motion has a name, which state files record (a file naming a motion this build does not
// know is refused).
struct FixedMotion {
    static constexpr std::string_view name = "fixed";
};

/// Eq. 17: h(t) = h0 + travel/2 (1 - cos(omega (t - start))) for 0 <= omega (t - start) <= pi,
/// omega = 2 pi / period; fixed at h0 + travel afterwards.
struct StrainControlled {
    static constexpr std::string_view name = "strain-controlled";
    double travel;          ///< distance moved along the inward normal (m); > 0 compresses
    double period;          ///< T of Eq. 17 (s); the motion takes T/2
    double start_time = 0;  ///< time at which the motion starts (s)
};

/// Eq. 18: the wall is a mass on a damper, pushed inward by pressure times its area.
///
/// Eq. 18's damper is anchored to the lab, so a wall that must keep moving (the side wall of a
/// biaxial test moves as fast as the loaded one) feels gamma_w h' on top of p A: strong damping
/// biases the pressure. With `follow_time` > 0 the damper's anchor instead follows the wall's
/// velocity with that time constant: steady motion is not resisted (the bias falls to gamma_w
/// times follow_time times the wall's acceleration), oscillations faster than 1 / follow_time
/// are damped as by Eq. 18.
struct StressControlled {
    static constexpr std::string_view name = "stress-controlled";
    double pressure;  ///< p (N/m in 2D, Pa in 3D)
    double mass;      ///< m_w (kg)
    double damping;   ///< gamma_w (kg/s)
    double area = 0;  ///< A (m in 2D, m^2 in 3D); 0 = the box cross-section, measured each step
    double follow_time = 0;   ///< s; 0 = Eq. 18 (damper anchored to the lab)
    double anchor_speed = 0;  ///< state: the damper anchor's velocity (m/s)

    /// The velocity the damper resists.
    double damped_speed(double wall_speed) const { return follow_time > 0 ? wall_speed - anchor_speed : wall_speed; }
};

using WallMotion = std::variant<FixedMotion, StrainControlled, StressControlled>;

template <int dim>
struct Wall {
    using V = Vec<dim>;
    V normal;                     ///< unit, into the domain
    double offset;                ///< h: the plane is {x : normal . x = h}
    WallMotion motion = FixedMotion{};
    double speed = 0.0;           ///< dh/dt
    double initial_offset = 0.0;  ///< h at time 0 (Eq. 17's reference)
    V force = V::Zero();          ///< force ON the wall from the particles, last evaluation
    bool frictionless = false;    ///< use only the normal part of the contact law on this wall

    /// Signed distance of a point from the plane, positive inside the domain.
    double distance(const V& x) const { return normal.dot(x) - offset; }
    /// The axis this wall is perpendicular to, or -1.
    int axis() const {
        for (int k = 0; k < dim; ++k)
            if (std::abs(std::abs(normal[k]) - 1.0) < 1e-14) return k;
        return -1;
    }
    /// Coordinate of an axis-aligned wall along its axis.
    double coordinate() const { return normal[axis()] > 0 ? offset : -offset; }
};

/// No walls: a scene without them compiles no wall code.
struct NoWalls {};

template <int dim>
class Walls {
public:
    using V = Vec<dim>;

    /// A plane through `point` with inward normal `normal` (normalised here).
    Wall<dim>& add(const V& normal, const V& point, WallMotion motion = FixedMotion{}) {
        const double length = normal.norm();
        if (!(length > 0.0) || !std::isfinite(length))
            detail::throw_input_error("wall ", walls_.size(), ": normal has length ", length,
                                      "; give a finite, non-zero normal pointing into the domain");
        for (int k = 0; k < dim; ++k)
            if (!std::isfinite(point[k]))
                detail::throw_input_error("wall ", walls_.size(), ": point component ", k, " = ", point[k],
                                          " is not finite");
        Wall<dim> w{normal / length, 0.0, motion};
        w.offset = w.normal.dot(point);
        w.initial_offset = w.offset;
        validate(w);
        walls_.push_back(w);
        return walls_.back();
    }

    /// A wall perpendicular to `axis` at `coordinate`; `lower` walls face +axis, upper ones -axis.
    Wall<dim>& add_axis_aligned(int axis, bool lower, double coordinate, WallMotion motion = FixedMotion{}) {
        V n = V::Zero();
        n[axis] = lower ? 1.0 : -1.0;
        V p = V::Zero();
        p[axis] = coordinate;
        return add(n, p, motion);
    }

    /// The 2 dim walls of the box [lo, hi], all fixed; index 2k is the lower wall of axis k.
    void add_box(const V& lo, const V& hi) {
        for (int k = 0; k < dim; ++k) {
            add_axis_aligned(k, true, lo[k]);
            add_axis_aligned(k, false, hi[k]);
        }
    }

    std::size_t size() const { return walls_.size(); }

    /// The box's mean flow: along every axis bounded by a lower and an upper axis-aligned wall
    /// (the first of each found), the velocity that grows linearly from the lower wall's to the
    /// upper wall's; zero along other axes. A packing that follows its walls affinely moves with
    /// this field.
    AffineField<dim> affine_field() const {
        AffineField<dim> field;
        for (int k = 0; k < dim; ++k) {
            const Wall<dim>* lower = nullptr;
            const Wall<dim>* upper = nullptr;
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
    /// new reference of Eq. 17.
    void deform(const Eigen::Matrix<double, dim, dim>& F) {
        const Eigen::Matrix<double, dim, dim> normal_map = F.inverse().transpose();
        for (auto& w : walls_) {
            const V point = F * (w.offset * w.normal);
            w.normal = (normal_map * w.normal).normalized();
            w.offset = w.normal.dot(point);
            w.initial_offset = w.offset;
        }
    }

    /// The kinetic energy 1/2 m_w v^2 of the stress-controlled walls (the others have no mass).
    double kinetic_energy() const {
        double e = 0.0;
        for (const auto& w : walls_)
            if (const auto* s = std::get_if<StressControlled>(&w.motion)) e += 0.5 * s->mass * w.speed * w.speed;
        return e;
    }

    /// Calls refuse(message parts...) for the first wall whose position or speed is not finite
    /// (a restored state that must not run).
    template <class Refuse>
    void check_restored(Refuse&& refuse) const {
        for (std::size_t w = 0; w < walls_.size(); ++w)
            if (!walls_[w].normal.allFinite() || !std::isfinite(walls_[w].offset) || !std::isfinite(walls_[w].speed))
                refuse("wall ", w, " has a position or speed that is not finite");
    }

    template <class Archive>
    void serialize(Archive& ar) {
        std::size_t n = walls_.size();
        ar.value(n);
        walls_.resize(n);
        for (auto& w : walls_) {
            ar.value(w.normal);
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

    Wall<dim>& operator[](std::size_t w) { return walls_[w]; }
    const Wall<dim>& operator[](std::size_t w) const { return walls_[w]; }
    auto begin() { return walls_.begin(); }
    auto end() { return walls_.end(); }
    auto begin() const { return walls_.begin(); }
    auto end() const { return walls_.end(); }

    /// The cross-section a stress-controlled wall pushes on: its own area if given, else the
    /// product of the box extents along the other axes (between opposite walls, or the periodic
    /// length).
    double area(const Wall<dim>& w, const Domain<dim>& domain) const {
        const auto& s = std::get<StressControlled>(w.motion);
        if (s.area > 0.0) return s.area;
        const int a = w.axis();
        double area = 1.0;
        for (int k = 0; k < dim; ++k) {
            if (k == a) continue;
            const Wall<dim>* lo = nullptr;
            const Wall<dim>* hi = nullptr;
            for (const auto& o : walls_)
                if (o.axis() == k) (o.normal[k] > 0 ? lo : hi) = &o;
            if (lo && hi) area *= hi->coordinate() - lo->coordinate();
            else if (domain.periodic(k)) area *= domain.length(k);
            else
                detail::throw_input_error("stress-controlled wall: axis ", k,
                                          " has neither two opposite walls nor periodicity, so the wall area is "
                                          "undefined; set StressControlled::area");
        }
        return area;
    }

    /// Moves every wall from time t to t + dt. Stress-controlled walls use the wall force of the
    /// last evaluation (semi-implicit Euler: velocity first, then position).
    void move(double t, double dt, const Domain<dim>& domain) {
        for (auto& w : walls_) {
            if (auto* s = std::get_if<StrainControlled>(&w.motion)) {
                const double omega = 2.0 * std::numbers::pi / s->period;
                const double phase = std::clamp(omega * (t + dt - s->start_time), 0.0, std::numbers::pi);
                w.offset = w.initial_offset + 0.5 * s->travel * (1.0 - std::cos(phase));
                w.speed = (phase > 0.0 && phase < std::numbers::pi) ? 0.5 * s->travel * omega * std::sin(phase) : 0.0;
            } else if (auto* p = std::get_if<StressControlled>(&w.motion)) {
                const double push = p->pressure * area(w, domain) + w.force.dot(w.normal);
                w.speed += dt * (push - p->damping * p->damped_speed(w.speed)) / p->mass;
                w.offset += dt * w.speed;
                if (p->follow_time > 0) p->anchor_speed += (w.speed - p->anchor_speed) * std::min(1.0, dt / p->follow_time);
            }
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

    static void validate(const Wall<dim>& w) {
        if (const auto* s = std::get_if<StrainControlled>(&w.motion)) {
            detail::require_positive(s->period, "StrainControlled::period", "give the period T of Eq. 17 in s");
            if (!std::isfinite(s->travel)) detail::throw_input_error("StrainControlled::travel = ", s->travel, " is not finite");
        } else if (const auto* p = std::get_if<StressControlled>(&w.motion)) {
            detail::require_non_negative(p->pressure, "StressControlled::pressure", "walls cannot pull");
            detail::require_positive(p->mass, "StressControlled::mass", "give the wall mass m_w of Eq. 18 in kg");
            detail::require_non_negative(p->damping, "StressControlled::damping", "give gamma_w of Eq. 18 in kg/s");
            detail::require_non_negative(p->area, "StressControlled::area", "use 0 for the box cross-section");
            detail::require_non_negative(p->follow_time, "StressControlled::follow_time", "use 0 for Eq. 18's damper");
            if (w.axis() < 0 && p->area == 0.0)
                detail::throw_input_error("a stress-controlled wall that is not axis-aligned needs an explicit area");
        }
    }

    std::vector<Wall<dim>> walls_;
};

}  // namespace micromacro
