#pragma once
// How a wall moves: its motion policy acts on one coordinate, the offset h by which the wall's
// shape is translated along its direction (for a plane, h of n . x = h along the inward normal n,
// so "travel > 0" compresses).
//   FixedMotion       never moves;
//   StrainControlled  moves by Eq. 17 (a cosine ramp of given travel and period, then stops);
//   StressControlled  obeys Eq. 18, m_w h'' = p A - F - gamma_w h', F the push of the particles.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>
#include <variant>

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
    double travel;          ///< distance moved along the wall's direction (m); > 0 compresses
    double period;          ///< T of Eq. 17 (s); the motion takes T/2
    double start_time = 0;  ///< time at which the motion starts (s)

    /// The offset and its rate at time t, from the offset h0 at the start.
    std::pair<double, double> at(double t, double h0) const {
        const double omega = 2.0 * std::numbers::pi / period;
        const double phase = std::clamp(omega * (t - start_time), 0.0, std::numbers::pi);
        const double speed = (phase > 0.0 && phase < std::numbers::pi) ? 0.5 * travel * omega * std::sin(phase) : 0.0;
        return {h0 + 0.5 * travel * (1.0 - std::cos(phase)), speed};
    }
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

    /// One step of Eq. 18 (semi-implicit Euler: velocity first, then position) for a wall with
    /// offset h and speed v, pushed by p A + `load` (the particles' force along the wall's
    /// direction, < 0 when they push it back).
    void advance(double area_now, double load, double dt, double& h, double& v) {
        const double push = pressure * area_now + load;
        v += dt * (push - damping * damped_speed(v)) / mass;
        h += dt * v;
        if (follow_time > 0) anchor_speed += (v - anchor_speed) * std::min(1.0, dt / follow_time);
    }
};

using WallMotion = std::variant<FixedMotion, StrainControlled, StressControlled>;

namespace detail {

/// Refuses a motion whose parameters cannot run (`needs_explicit_area`: the wall is not an
/// axis-aligned plane, so there is no box cross-section and a stress-controlled motion must give
/// its area).
inline void validate_motion(const WallMotion& motion, bool needs_explicit_area) {
    if (const auto* s = std::get_if<StrainControlled>(&motion)) {
        require_positive(s->period, "StrainControlled::period", "give the period T of Eq. 17 in s");
        if (!std::isfinite(s->travel)) throw_input_error("StrainControlled::travel = ", s->travel, " is not finite");
    } else if (const auto* p = std::get_if<StressControlled>(&motion)) {
        require_non_negative(p->pressure, "StressControlled::pressure", "walls cannot pull");
        require_positive(p->mass, "StressControlled::mass", "give the wall mass m_w of Eq. 18 in kg");
        require_non_negative(p->damping, "StressControlled::damping", "give gamma_w of Eq. 18 in kg/s");
        require_non_negative(p->area, "StressControlled::area", "use 0 for the box cross-section");
        require_non_negative(p->follow_time, "StressControlled::follow_time", "use 0 for Eq. 18's damper");
        if (needs_explicit_area && p->area == 0.0)
            throw_input_error("a stress-controlled wall that is not axis-aligned needs an explicit area "
                              "(StressControlled::area): only an axis-aligned plane has the box's cross-section");
    }
}

}  // namespace detail
}  // namespace micromacro
