#pragma once
// An element test's drive: each component (i, k), i <= k, of a periodic cell's velocity gradient
// L (upper triangular, Domain::set_velocity_gradient) is either held at zero, prescribed (a
// rate, or a strain path F_ik(t) of the cell's deformation gradient), or servo-controlled to a
// target component of the cell's stress, which the averaging layer takes over the whole cell
// (contact and kinetic parts). The controller sets L at the start of each interval of steps
// from the stress measured then, and follows the cell's deformation gradient F (the lattice
// over its starting one, tilts not re-based), stepping it as Domain::advance steps the lattice.
//
// The servo is proportional: L_ik = gain (sigma_ik - target_ik), limited to +-max_rate, sigma_ik the
// symmetric part (sigma_ik + sigma_ki) / 2 (a packing not at rest has some asymmetry). Stress is
// compression positive, so an excess expands the cell (or shears it further in the sense that
// lowers sigma_ik). Its steady error is the rate the loading asks of the component divided by
// the gain, which vanishes in the quasi-static limit whatever the gain: docs/element-tests.md
// measures how little the result depends on it. Or the gain follows the packing
// (following_stiffness): a stress error e asks for e / (C_ikik tau), C = C^n + C^t the averaged
// stiffness of the same measurement, an upper bound of the packing's incremental modulus, so the
// servo closes an error in about tau at any pressure and contact stiffness, and a gas (C = 0) is
// compressed (or expanded) at max_rate, its shape held.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <string>

#include "micromacro/averaging/micro_macro.hpp"
#include "micromacro/averaging/region.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/engine/snapshot.hpp"

namespace micromacro {

template <int dim>
class CellControl {
public:
    using Matrix = Eigen::Matrix<double, dim, dim>;
    /// What the servos act on: the cell's stress (contact and kinetic, compression positive) and,
    /// per component (i, k), the averaged stiffness C^n_ikik + C^t_ikik.
    struct Reading {
        Matrix stress = Matrix::Zero();
        Matrix stiffness = Matrix::Zero();
    };
    /// F_ik as a function of the time since the control started (s).
    using StrainPath = std::function<double(double)>;

    /// gain: the servo's strain rate per unit stress error (1/(Pa s) in 3D, 1/((N/m) s) in 2D);
    /// max_rate: the largest strain rate a servo asks for (1/s); interval: steps between
    /// measurements of the stress (and updates of L).
    CellControl(double gain, double max_rate, std::size_t interval = 10) : gain_(gain), max_rate_(max_rate), interval_(interval) {
        detail::require_non_negative(gain, "cell servo gain", "use 0 for servos that hold their components still");
        detail::require_positive(max_rate, "cell servo's largest strain rate", "give the fastest rate a servo may drive, in 1/s");
        if (interval == 0) detail::throw_input_error("CellControl: the measuring interval is 0 steps; it must be at least 1");
    }

    /// A servo whose gain follows the packing's averaged stiffness: it closes a stress error in
    /// about `time` (s; the interval's length at the least, or it would overshoot), within
    /// +-max_rate (1/s).
    static CellControl following_stiffness(double time, double max_rate, std::size_t interval = 10) {
        detail::require_positive(time, "cell servo's relaxation time", "give the time in which the servo closes a stress error, in s");
        CellControl c(0.0, max_rate, interval);
        c.relaxation_time_ = time;
        return c;
    }

    /// L_ik held at `rate` (1/s): a stretch rate for i = k, a shear rate of axis i along k for i < k.
    CellControl& rate(int i, int k, double rate) { return set(i, k, {Kind::rate, rate, {}, 0.0}); }
    /// F_ik follows `path` (F_kk = 1 + engineering strain, F_ik = shear strain for i < k).
    CellControl& strain_path(int i, int k, StrainPath path) { return set(i, k, {Kind::path, 0.0, std::move(path), 0.0}); }
    /// sigma_ik servo-controlled to `target` (Pa in 3D, N/m in 2D; compression positive).
    CellControl& stress(int i, int k, double target) { return set(i, k, {Kind::stress, 0.0, {}, target}); }
    /// The stress servo-controlled to the isotropic p 1: every normal stress to p, every shear
    /// stress to zero (isotropic loading; held at zero rate, the shears would keep what the
    /// packing's preparation left them).
    CellControl& pressure(double p) {
        for (int k = 0; k < dim; ++k)
            for (int i = 0; i <= k; ++i) stress(i, k, i == k ? p : 0.0);
        return *this;
    }
    /// L_ik held at zero (the default of every component).
    CellControl& hold(int i, int k) { return set(i, k, {}); }

    bool servoed(int i, int k) const { return component_[i][k].kind == Kind::stress; }
    double target(int i, int k) const { return component_[i][k].target; }

    /// The cell's averages over its whole volume, kinetic stress included (relative to the flow).
    template <class Sim>
    static MicroMacro<dim> measure(const Sim& sim) {
        return measure(take_snapshot(sim));
    }
    /// The same of a snapshot of the cell.
    static MicroMacro<dim> measure(const PackingSnapshot<dim>& s) {
        AveragingOptions opt;
        opt.kinetic_stress = true;
        return average(s, Region<dim>::whole(s), opt);
    }

    /// What a servo reads of the cell: measure()'s stress, the same sums in the same order (so the
    /// same numbers), and the stiffness entries C^n_ikik + C^t_ikik, added straight from the
    /// simulation's contacts without a snapshot or the rest of the average (which would cost a
    /// servoed run as much again as its steps). A cell with a wall is read through measure().
    template <class Sim>
    static Reading read(const Sim& sim) {
        const Domain<dim>& domain = sim.domain();
        bool periodic = true;
        for (int a = 0; a < dim; ++a) periodic = periodic && domain.periodic(a);
        if (!periodic) {
            const MicroMacro<dim> m = measure(sim);
            Reading r{m.stress, Matrix::Zero()};
            for (int k = 0; k < dim; ++k)
                for (int i = 0; i < dim; ++i) r.stiffness(i, k) = m.stiffness_normal(i, k, i, k) + m.stiffness_tangential(i, k, i, k);
            return r;
        }
        const double V = (domain.hi() - domain.lo()).prod();  // Region::whole's volume, as measure() divides by it
        const double w = 1.0 / V;
        Matrix normal = Matrix::Zero(), tangential = Matrix::Zero(), kinetic = Matrix::Zero();
        Matrix stiffness_normal = Matrix::Zero(), stiffness_tangential = Matrix::Zero();
        sim.for_each_contact([&](const ContactView<dim>& v) {  // as ContactSums::add, with w = 1 / V
            const Vec<dim> n = v.wall ? v.geometry.normal : Vec<dim>(v.branch / v.branch.norm());
            normal += (w * v.normal_force) * v.branch * n.transpose();
            tangential += w * v.branch * v.tangential_force.transpose();
            const double l2 = v.branch.squaredNorm(), cn = w * v.stiffness * l2, ct = w * v.tangential_stiffness * l2;
            for (int k = 0; k < dim; ++k)
                for (int i = 0; i < dim; ++i) {  // Tensor4::add_outer's n_i n_k n_i n_k, add_tangential's n_i n_i (1 - n_k n_k)
                    stiffness_normal(i, k) += cn * (n[i] * n[k]) * (n[i] * n[k]);
                    stiffness_tangential(i, k) += ct * n[i] * n[i] * (1.0 - n[k] * n[k]);
                }
        });
        const auto& p = sim.particles();
        const Matrix& L = domain.velocity_gradient();
        for (std::size_t q = 0; q < p.size(); ++q) {
            Vec<dim> u = convert<double>(p.velocity()[q]);
            if (domain.moving()) u -= L * (convert<double>(p.position()[q]) - domain.centre());
            kinetic += p.mass()[q] * u * u.transpose() / V;
        }
        return {normal + tangential + kinetic, stiffness_normal + stiffness_tangential};
    }

    /// One interval: measures the stress where a servo needs it, sets L, runs the steps (at most
    /// `steps`, default the interval) and steps F. Returns the steps run.
    template <class Sim>
    std::size_t step(Sim& sim, std::size_t steps = 0) {
        const std::size_t n = steps == 0 ? interval_ : std::min(steps, interval_);
        const double dt = sim.time_step(), span = double(n) * dt;
        if (any_servo()) last_ = read(sim);
        const Matrix L = gradient(span);
        sim.set_velocity_gradient(L);
        sim.run(n);
        const Matrix step = Matrix::Identity() + L * dt + 0.5 * (L * dt) * (L * dt);  // as Domain::advance
        for (std::size_t s = 0; s < n; ++s) deformation_ = (step * deformation_).eval();
        time_ += span;
        return n;
    }

    /// Runs `steps` steps, interval by interval.
    template <class Sim>
    void run(Sim& sim, std::size_t steps) {
        for (std::size_t done = 0; done < steps;) done += step(sim, steps - done);
    }

    /// F: the cell's deformation since the control started (its lattice over the lattice then).
    const Matrix& deformation() const { return deformation_; }
    /// The time the control has run (s).
    double time() const { return time_; }
    /// Continues a control saved at an interval's end (a checkpoint): its deformation F and time.
    /// The components are the caller's to set again (a strain path is a function); the servos
    /// measure afresh at the next interval's start, as they would have.
    void resume_at(const Matrix& deformation, double time) {
        if (!deformation.allFinite() || !std::isfinite(time) || time < 0.0)
            detail::throw_input_error("CellControl: a saved control with a non-finite deformation or a time of ", time,
                                      " s cannot be continued");
        deformation_ = deformation;
        time_ = time;
    }
    /// What the servos last read (zero before the first interval with a servo).
    const Reading& last_reading() const { return last_; }

private:
    enum class Kind { hold, rate, path, stress };
    struct Component {
        Kind kind = Kind::hold;
        double rate = 0.0;
        StrainPath path;
        double target = 0.0;
    };

    CellControl& set(int i, int k, Component c) {
        if (i < 0 || k >= dim || i > k)
            detail::throw_input_error("CellControl: component (", i, ", ", k, ") is not on or above the diagonal of a ", dim,
                                      "D cell's velocity gradient; give (i, k) with 0 <= i <= k < ", dim,
                                      " (every deformation is an upper-triangular one up to a rotation)");
        if (c.kind == Kind::rate && !std::isfinite(c.rate))
            detail::throw_input_error("CellControl: the rate of component (", i, ", ", k, ") is ", c.rate, "; it must be finite");
        if (c.kind == Kind::stress && !std::isfinite(c.target))
            detail::throw_input_error("CellControl: the stress target of component (", i, ", ", k, ") is ", c.target,
                                      "; it must be finite");
        if (c.kind == Kind::path && !c.path)
            detail::throw_input_error("CellControl: the strain path of component (", i, ", ", k, ") is empty");
        component_[i][k] = std::move(c);
        return *this;
    }

    bool any_servo() const {
        for (int k = 0; k < dim; ++k)
            for (int i = 0; i <= k; ++i)
                if (component_[i][k].kind == Kind::stress) return true;
        return false;
    }

    // L for the next `span` seconds, column by column: a path's off-diagonal entry needs the
    // entries of its row in the columns before (dF/dt = L F, both upper triangular).
    Matrix gradient(double span) const {
        Matrix L = Matrix::Zero();
        for (int k = 0; k < dim; ++k)
            for (int i = k; i >= 0; --i) {
                const Component& c = component_[i][k];
                switch (c.kind) {
                    case Kind::hold: break;
                    case Kind::rate: L(i, k) = c.rate; break;
                    case Kind::stress: L(i, k) = std::clamp(servo_rate(i, k, c.target), -max_rate_, max_rate_); break;
                    case Kind::path: L(i, k) = path_rate(L, i, k, c.path(time_ + span), span); break;
                }
            }
        return L;
    }

    // The servo's rate for component (i, k), before the limit.
    double servo_rate(int i, int k, double target) const {
        const double error = 0.5 * (last_.stress(i, k) + last_.stress(k, i)) - target;
        if (relaxation_time_ == 0.0) return gain_ * error;
        const double C = last_.stiffness(i, k);
        if (C > 0.0) return error / (C * relaxation_time_);
        return i == k && error != 0.0 ? std::copysign(max_rate_, error) : 0.0;  // a gas: closed at the limit, not sheared
    }

    // The rate that brings F_ik to `goal` over `span`, the row's other entries given.
    double path_rate(const Matrix& L, int i, int k, double goal, double span) const {
        const Matrix& F = deformation_;
        if (i == k) {
            if (!(goal > -1.0))
                detail::throw_input_error("CellControl: the strain path of axis ", k, " asks for ", goal,
                                          ", a length of ", 1.0 + goal, " times the start; it must stay above -1");
            return std::log((1.0 + goal) / F(k, k)) / span;
        }
        double others = 0.0;
        for (int j = i; j < k; ++j) others += L(i, j) * F(j, k);
        return ((goal - F(i, k)) / span - others) / F(k, k);
    }

    double gain_, max_rate_, relaxation_time_ = 0.0;
    std::size_t interval_;
    Component component_[dim][dim];
    Matrix deformation_ = Matrix::Identity();
    double time_ = 0.0;
    Reading last_;
};

}  // namespace micromacro
