#pragma once
// The Hertz-Mindlin contact law of elastic spheres (disks take the same law, as in most DEM
// codes), with a viscous damping that gives one restitution coefficient at every impact speed,
// and Coulomb friction on Mindlin's no-slip tangential spring. One file: the engine reaches it
// through the ContactLawModel concept only.
//
// Normal: f_n = k_n delta^(3/2) - alpha sqrt(m* k_n) delta^(1/4) v_n, with k_n = (4/3) E* sqrt(R*),
// E* = E / (2 (1 - nu^2)) between two particles of one material and E / (1 - nu^2) on a rigid
// wall. In the units delta = L x, t = T tau with T^2 = m* / (k_n L^(1/2)) the motion of a head-on
// collision is x'' = -x^(3/2) - alpha x^(1/4) x', the same for every impact speed: the
// restitution depends on alpha alone (Tsuji et al. 1992), and the constructor finds the alpha
// of the restitution asked for by integrating that equation once.
// Tangential: the built-in spring of Eq. 23-29 (CundallStrack, with its second-order update and
// Coulomb limit) with Mindlin's stiffness k_t = 8 G* sqrt(R* delta), G* = G / (2 (2 - nu)) between
// particles and G / (2 - nu) on a wall, G = E / (2 (1 + nu)), and a dashpot of the normal one's
// damping ratio. The stiffnesses follow the overlap, so the stable time step is bounded at the
// largest overlap the user expects (`largest_overlap`, relative to R*).
#include <algorithm>
#include <cmath>

#include "micromacro/contact/contact_law.hpp"
#include "micromacro/contact/geometry.hpp"
#include "micromacro/contact/normal.hpp"
#include "micromacro/contact/tangential.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/inline.hpp"

namespace micromacro {

class HertzMindlin {
public:
    static constexpr bool has_tangential = true;
    static constexpr bool has_history = true;
    static constexpr bool needs_rotation = true;
    template <int dim>
    using History = TangentialSpring<dim>;

    /// Young's modulus E (Pa) and Poisson's ratio nu of the particles' material (a wall is
    /// rigid), the normal restitution e in (0, 1], the friction coefficient mu, and the largest
    /// overlap expected, relative to R*, for the stable time step.
    HertzMindlin(double young, double poisson, double restitution, double mu, double largest_overlap = 0.05)
        : young_(young), poisson_(poisson), restitution_(restitution), largest_overlap_(largest_overlap),
          friction_(1.0, 0.0, mu) {
        require_positive(young, "Young's modulus E", "give it in Pa, e.g. 7e10 for glass");
        if (!(poisson > -1.0 && poisson < 0.5))
            throw_input_error("Poisson's ratio nu = ", poisson, " is outside (-1, 0.5); e.g. 0.25 for glass");
        if (!(restitution > 0.0 && restitution <= 1.0))
            throw_input_error("restitution e = ", restitution, " is outside (0, 1]; use 1 for elastic contacts");
        require_positive(largest_overlap, "largest expected overlap / R*", "e.g. 0.05");
        alpha_ = damping_for_restitution(restitution);
    }

    double young() const { return young_; }
    double poisson() const { return poisson_; }
    double restitution() const { return restitution_; }
    double mu() const { return friction_.mu_static(); }
    /// alpha of the damping term above.
    double damping_ratio() const { return alpha_; }

    /// E* and G* of a contact (`wall`: the partner is a rigid wall).
    double effective_young(bool wall) const { return young_ / ((wall ? 1.0 : 2.0) * (1.0 - poisson_ * poisson_)); }
    double effective_shear(bool wall) const {
        return young_ / (2.0 * (1.0 + poisson_)) / ((wall ? 1.0 : 2.0) * (2.0 - poisson_));
    }
    /// k_n = (4/3) E* sqrt(R*) of f_n = k_n delta^(3/2).
    double normal_coefficient(double effective_radius, bool wall = false) const {
        return 4.0 / 3.0 * effective_young(wall) * std::sqrt(effective_radius);
    }
    /// The overlap at which the elastic normal force is `force` (for a packing under a given load).
    double overlap_for_force(double force, double effective_radius, bool wall = false) const {
        return std::pow(force / normal_coefficient(effective_radius, wall), 2.0 / 3.0);
    }

    template <bool track, int dim>
    MICROMACRO_INLINE ContactForce<dim> force(const ContactKinematics<dim>& c, History<dim>& h) const {
        const Springs s = springs(c);
        const NormalForce fn = s.normal(c.overlap, c.normal_velocity);
        return {fn, friction_.with_stiffness(s.kt, s.gamma_t)
                        .template force<dim, track>(c.normal, c.relative_velocity, c.normal_velocity, fn.total(), c.overlap, c.dt, h)};
    }

    template <int dim>
    NormalForce normal_force(const ContactKinematics<dim>& c) const {
        return springs(c).normal(c.overlap, c.normal_velocity);
    }

    template <int dim>
    ContactState<dim> state(const ContactKinematics<dim>& c, const History<dim>* h) const {
        const Springs s = springs(c);
        ContactState<dim> out;
        const double d = std::max(c.overlap, 0.0);
        out.normal = s.normal(c.overlap, c.normal_velocity);
        out.normal_energy = 0.4 * s.kn * d * d * std::sqrt(d);  // the integral of k_n delta^(3/2)
        out.stiffness = 1.5 * s.kn * std::sqrt(d);
        if (!h) return out;
        const CundallStrack spring = friction_.with_stiffness(s.kt, s.gamma_t);
        out.tangential = spring.current_force(c.normal, c.relative_velocity, out.normal.total(), *h);
        out.tangential_energy = spring.elastic_energy(spring.present_spring(c.normal, *h));
        out.tangential_stiffness = s.kt;
        out.sliding = h->sliding;
        return out;
    }

    /// The stiffnesses and dampings at the largest expected overlap, between particles.
    StiffnessBound stiffness_bound(double effective_radius, double effective_mass) const {
        const double d = largest_overlap_ * effective_radius;
        const Springs s = springs_at(effective_radius, effective_mass, d, false);
        return {1.5 * s.kn * std::sqrt(d), s.damping(d), s.kt, s.gamma_t};
    }

    template <int dim>
    bool touched(const History<dim>& h) const {
        return h.touching;
    }

    /// Nothing to add when a contact opens: Mindlin's k_t vanishes with the overlap, so the
    /// spring's force falls to zero continuously (the linear spring's does not, see
    /// CundallStrack::opening_correction).
    template <int dim>
    Vec<dim> opening_force(const ContactKinematics<dim>&, const History<dim>&) const {
        return Vec<dim>::Zero();
    }

    template <int dim>
    void step_back(const Vec<dim>& n, const Vec<dim>& relative_velocity, double dt_last, double dt_next, History<dim>& h) const {
        friction_.step_back(n, relative_velocity, dt_last, dt_next, h);
    }

    template <int dim>
    void displace(const Vec<dim>& n, const Vec<dim>& tangential_displacement, History<dim>& h) const {
        friction_.displace(n, tangential_displacement, h);
    }

    /// The restitution of x'' = -x^(3/2) - alpha x^(1/4) x' (see above), by the classical
    /// Runge-Kutta method in steps of 1/4000 of the elastic contact duration, the crossing of
    /// x = 0 interpolated: accurate to about 1e-5 (x^(1/4) is not smooth where the contact ends;
    /// 1e-9 without damping).
    static double restitution_for_damping(double alpha) {
        const double h = 3.2181 / 4000;  // the elastic duration is 2.94323 (5/4)^(2/5) = 3.2181
        auto acceleration = [alpha](double x, double v) {
            const double q = std::sqrt(std::sqrt(std::max(x, 0.0)));  // x^(1/4)
            return -q * q * q * q * q * q - alpha * q * v;
        };
        double x = 0.0, v = 1.0;
        for (int step = 0; step < 1000000; ++step) {
            const double k1x = v, k1v = acceleration(x, v);
            const double k2x = v + 0.5 * h * k1v, k2v = acceleration(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
            const double k3x = v + 0.5 * h * k2v, k3v = acceleration(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
            const double k4x = v + h * k3v, k4v = acceleration(x + h * k3x, v + h * k3v);
            const double x_next = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            const double v_next = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            if (x_next <= 0.0 && step > 0) {  // parted within this step: the velocity where x = 0
                const double f = x / (x - x_next);
                return -(v + f * (v_next - v));
            }
            x = x_next;
            v = v_next;
        }
        return 0.0;  // still in contact after 250 elastic durations: stuck
    }

    /// The alpha whose restitution is e, by bisection on restitution_for_damping (decreasing).
    static double damping_for_restitution(double e) {
        if (e >= 1.0) return 0.0;
        double low = 0.0, high = 1.0;
        while (restitution_for_damping(high) > e) high *= 2.0;
        for (int i = 0; i < 50 && high - low > 1e-12 * high; ++i) {
            const double mid = 0.5 * (low + high);
            (restitution_for_damping(mid) > e ? low : high) = mid;
        }
        return 0.5 * (low + high);
    }

private:
    struct Springs {
        double kn, coefficient, kt, gamma_t;  // f_n = kn d^(3/2) - coefficient d^(1/4) v_n
        double damping(double d) const { return coefficient * std::sqrt(std::sqrt(d)); }
        NormalForce normal(double overlap, double normal_velocity) const {
            const double d = std::max(overlap, 0.0), root = std::sqrt(d);
            return {kn * d * root, -coefficient * std::sqrt(root) * normal_velocity};
        }
    };

    Springs springs_at(double effective_radius, double effective_mass, double overlap, bool wall) const {
        const double d = std::max(overlap, 0.0), contact_radius = std::sqrt(effective_radius * d);
        const double kn = normal_coefficient(effective_radius, wall);
        const double kt = 8.0 * effective_shear(wall) * contact_radius;
        // The tangential dashpot has the normal one's ratio to its critical damping: with
        // alpha sqrt(m* k_n) d^(1/4) = alpha sqrt(2/3) sqrt(m* S_n), S_n = 1.5 k_n sqrt(d).
        const double gamma_t = alpha_ * std::sqrt(2.0 / 3.0 * effective_mass * kt);
        return {kn, alpha_ * std::sqrt(effective_mass * kn), kt, gamma_t};
    }
    template <int dim>
    Springs springs(const ContactKinematics<dim>& c) const {
        return springs_at(c.effective_radius(), c.effective_mass(), c.overlap, std::isinf(c.radius_j));
    }

    double young_, poisson_, restitution_, largest_overlap_;
    double alpha_ = 0.0;
    CundallStrack friction_;  // mu and the spring's update; its stiffness is set per contact
};
static_assert(ContactLawModel<HertzMindlin>);

}  // namespace micromacro
