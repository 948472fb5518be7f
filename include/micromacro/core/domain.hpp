#pragma once
// The simulation box, which of its axes are periodic, and how its periodic images lie and move.
//
// Periodic axes wrap positions into [lo, hi) and measure separations by the minimum image, so a
// pair keeps its identity (and its tangential spring) when one partner crosses the boundary.
// Non-periodic axes are open: particles are held in by walls (or not at all).
//
// A periodic cell may be sheared by Lees-Edwards images: the image across the faces of axis k is
// shifted by tilt(i, k) along each periodic axis i < k, so the lattice of images has the columns
//     lattice() = [ L_0  t_01  t_02 ]
//                 [  0   L_1   t_12 ]
//                 [  0    0    L_2  ]
// (upper triangular, as LAMMPS's restricted triclinic box), while positions stay in the
// orthogonal box [lo, hi), a fundamental domain of that lattice at any tilt. A tilt is kept
// within half a period (a tilt of one period is the same lattice), so the cell never distorts and
// a shear strain has no bound. A moving cell has a velocity gradient L (upper triangular, the
// flow x' = L x about the box's centre): the box deforms with it (advance), and an image shifted
// by D moves at L D relative to its original, which the engine adds to a pair's relative
// velocity across the boundary and takes from a particle's velocity when it wraps (as LAMMPS's
// fix deform with remap v, YADE's cell shift velocity and MercuryDPM's Lees-Edwards boundary).
// docs/model.md argues the choice.
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/inline.hpp"

namespace micromacro {

template <int dim>
class Domain {
public:
    using V = Vec<dim>;
    using Matrix = Eigen::Matrix<double, dim, dim>;

    /// An unbounded domain: no periodic axis.
    Domain() : lo_(V::Zero()), hi_(V::Zero()) {
        periodic_.fill(false);
        refresh();
    }

    /// A box [lo, hi) with the given periodic axes.
    Domain(const V& lo, const V& hi, std::array<bool, dim> periodic) : lo_(lo), hi_(hi), periodic_(periodic) {
        for (int a = 0; a < dim; ++a) {
            if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]) || !(hi[a] > lo[a]))
                detail::throw_input_error("Domain: axis ", a, " has lo = ", lo[a], " and hi = ", hi[a],
                                          "; a box needs finite bounds with hi > lo");
        }
        refresh();
    }

    /// A box [lo, hi) periodic on every axis (a representative volume without walls).
    static Domain fully_periodic(const V& lo, const V& hi) {
        std::array<bool, dim> all;
        all.fill(true);
        return Domain(lo, hi, all);
    }

    bool periodic(int axis) const { return periodic_[axis]; }
    bool any_periodic() const {
        for (bool p : periodic_)
            if (p) return true;
        return false;
    }
    const V& lo() const { return lo_; }
    const V& hi() const { return hi_; }
    V centre() const { return 0.5 * (lo_ + hi_); }
    double length(int axis) const { return hi_[axis] - lo_[axis]; }
    /// The box's volume (area in 2D): its lengths' product, at any tilt.
    double volume() const { return length_.prod(); }

    // ---- Lees-Edwards images ------------------------------------------------------------------
    /// The shift along axis i of the image across the faces of axis k (i < k, both periodic).
    double tilt(int i, int k) const { return lattice_(i, k); }
    bool tilted() const { return tilted_; }
    /// The lattice of images: column k is the shift of the image across axis k's faces.
    const Matrix& lattice() const { return lattice_; }
    /// Sets tilt(i, k) to t, kept within half a period of axis i (the same lattice).
    void set_tilt(int i, int k, double t) {
        check_pair("tilt", i, k, t);
        lattice_(i, k) = t;
        reduce_tilts();
        refresh();
    }

    // ---- a moving cell ------------------------------------------------------------------------
    /// The cell's velocity gradient L_ik = d v_i / d x_k (zero: a box at rest).
    const Matrix& velocity_gradient() const { return flow_; }
    bool moving() const { return moving_; }
    /// Upper triangular, with entries only between periodic axes (every homogeneous deformation up
    /// to a rigid rotation, docs/model.md); the box does not move until advance().
    void set_velocity_gradient(const Matrix& L) {
        for (int i = 0; i < dim; ++i)
            for (int k = 0; k < dim; ++k)
                if (L(i, k) != 0.0 || !std::isfinite(L(i, k))) check_pair("velocity gradient", i, k, L(i, k), i == k);
        flow_ = L;
        refresh();
    }
    /// The velocity of an image shifted by `shift` (a sum of lattice columns) relative to its original.
    V image_velocity(const V& shift) const { return flow_ * shift; }
    /// The box after a time dt of its velocity gradient: x -> (1 + L dt + (L dt)^2 / 2) x about its
    /// centre, which stays put. Returns whether a tilt passed half a period and was brought back
    /// (the same lattice with another column: a neighbour search must bin again).
    bool advance(double dt) {
        if (!moving_) return false;
        const Matrix step = flow_ * dt;
        lattice_ += step * lattice_ + 0.5 * step * (step * lattice_);
        const V c = centre();
        for (int k = 0; k < dim; ++k)
            if (periodic_[k]) lo_[k] = c[k] - 0.5 * lattice_(k, k), hi_[k] = c[k] + 0.5 * lattice_(k, k);
        const bool reduced = reduce_tilts();
        refresh();
        return reduced;
    }

    /// The box mapped by the deformation x -> F x. A box with periodic axes takes a diagonal F, or
    /// an upper triangular one whose off-diagonal entries join periodic axes (a tilt).
    Domain deformed(const Matrix& F) const {
        if (!any_periodic()) return *this;
        if (F.isDiagonal(0.0)) {
            Domain d(V(F * lo_), V(F * hi_), periodic_);
            d.lattice_ = F * lattice_;
            d.flow_ = flow_;
            d.reduce_tilts();
            d.refresh();
            return d;
        }
        for (int i = 0; i < dim; ++i)
            for (int k = 0; k < dim; ++k)
                if (i != k && F(i, k) != 0.0) check_pair("deformation", i, k, F(i, k));
        Domain d = *this;
        d.lattice_ = F * lattice_;
        const V c = F * centre();
        for (int k = 0; k < dim; ++k) d.lo_[k] = c[k] - 0.5 * d.lattice_(k, k), d.hi_[k] = c[k] + 0.5 * d.lattice_(k, k);
        d.reduce_tilts();
        d.refresh();
        return d;
    }

    /// Separation a - b, shortened to the nearest periodic image on periodic axes: the image in
    /// the orthogonal box around zero, which is the nearest one for every separation shorter than
    /// half the shortest period (check_interaction_range makes every pair that can touch one).
    MICROMACRO_INLINE V separation(const V& a, const V& b) const {
        V d = a - b;
        // Wrapped positions differ by less than L, so the image is needed only past half a box
        // length: one compare per axis (half_ is infinite on open axes), and the rare case out of
        // line, where its division and library call cannot crowd the pair loop's registers. From
        // the last axis down: a tilted image moves the lower axes, which are checked after.
        for (int k = dim - 1; k >= 0; --k)
            if (std::abs(d[k]) >= half_[k]) [[unlikely]] to_nearest_image(d, k);
        return d;
    }

    /// separation() where the caller has fixed at compile time whether the box has a periodic
    /// axis (the engine's loops are compiled for both): without one, a plain difference.
    template <bool any_periodic_axis>
    MICROMACRO_INLINE V separation_for(const V& a, const V& b) const {
        if constexpr (any_periodic_axis) return separation(a, b);
        else return a - b;
    }

    /// Maps a position back into [lo, hi) on periodic axes; leaves open axes alone.
    MICROMACRO_INLINE void wrap(V& x) const {
        V shift;
        wrap_position(x, shift);
    }
    /// wrap(x) and the velocity v of a particle at x: an image moves at image_velocity relative
    /// to its original, so a particle brought back by a shift D keeps its motion relative to the
    /// cell's flow by losing L D. Returns whether v changed.
    MICROMACRO_INLINE bool wrap(V& x, V& v) const {
        V shift;
        if (wrap_position(x, shift) && moving_) [[unlikely]] {
            v -= image_velocity(shift);
            return true;
        }
        return false;
    }

    template <class Archive>
    void serialize(Archive& ar) {
        ar.value(lo_);
        ar.value(hi_);
        ar.value(periodic_);
        ar.value(lattice_);
        ar.value(flow_);
        refresh();
    }

    /// A periodic axis must be at least two interaction ranges long, otherwise a particle would
    /// meet two images of the same partner and the minimum image would be ambiguous.
    void check_interaction_range(double range) const {
        if (const int k = axis_too_short(range); k >= 0)
            detail::throw_input_error("Domain: periodic axis ", k, " is ", length(k),
                                      " long, shorter than two interaction ranges (2 x ", range, " = ",
                                      2.0 * range, "); enlarge the box or use smaller particles");
    }

    /// The first periodic axis shorter than two interaction ranges, or -1 if there is none.
    int axis_too_short(double range) const {
        for (int k = 0; k < dim; ++k)
            if (periodic_[k] && length(k) < 2.0 * range) return k;
        return -1;
    }

private:
    // Brings d[k] within half a period by whole images across axis k (with their tilts).
    [[gnu::noinline]] void to_nearest_image(V& d, int k) const {
        if (!periodic_[k]) return;
        // Wrapped positions are less than a period apart: then the image is one period off, and
        // d -+ L is what the rounding below gives, without its division (the pairs across a
        // periodic boundary, a few percent of them, take this path).
        double n;
        if (std::abs(d[k]) < length_[k]) {
            n = d[k] > 0.0 ? 1.0 : -1.0;
            d[k] = d[k] > 0.0 ? d[k] - length_[k] : d[k] + length_[k];
        } else {
            n = std::round(d[k] / length_[k]);
            d[k] = d[k] - length_[k] * n;
        }
        for (int i = 0; i < k; ++i) d[i] -= n * lattice_(i, k);
    }

    // wrap(); `shift` the lattice vector taken off x. Returns whether x moved.
    MICROMACRO_INLINE bool wrap_position(V& x, V& shift) const {
        bool moved = false;
        for (int k = dim - 1; k >= 0; --k)
            if (periodic_[k] && (x[k] < lo_[k] || x[k] >= hi_[k])) [[unlikely]] {  // inside: nothing to do
                if (!moved) shift.setZero();
                moved = true;
                const double L = length_[k];
                double n = std::floor((x[k] - lo_[k]) / L);
                x[k] -= L * n;
                // Round-off can leave x a hair outside [lo, hi): at hi it is the next image's lo
                // (one more lattice vector, tilt included), below lo it is lo of the same image.
                if (x[k] >= hi_[k]) x[k] = lo_[k], n += 1.0;
                else if (x[k] < lo_[k]) x[k] = lo_[k];
                shift[k] += L * n;
                for (int i = 0; i < k; ++i) x[i] -= n * lattice_(i, k), shift[i] += n * lattice_(i, k);
            }
        return moved;
    }

    // A tilt, velocity gradient or deformation entry joins axes i and k: refused unless it may.
    void check_pair(const char* what, int i, int k, double value, bool diagonal = false) const {
        if (!std::isfinite(value))
            detail::throw_input_error("Domain: the ", what, " entry (", i, ", ", k, ") is ", value, "; it must be finite");
        if (diagonal) {
            if (!periodic_[k])
                detail::throw_input_error("Domain: the ", what, " entry (", k, ", ", k, ") = ", value, " stretches axis ", k,
                                          ", which is open; only periodic axes move with the cell (walls drive open ones)");
            return;
        }
        if (i < 0 || k >= dim || i >= k)
            detail::throw_input_error("Domain: the ", what, " entry (", i, ", ", k, ") = ", value,
                                      " is below the diagonal; a cell is sheared by entries (i, k) with i < k (upper "
                                      "triangular: every deformation up to a rotation), e.g. (0, 1) for x moving with y");
        if (!periodic_[i] || !periodic_[k])
            detail::throw_input_error("Domain: the ", what, " entry (", i, ", ", k, ") = ", value, " joins axis ", i,
                                      " and axis ", k, ", and axis ", periodic_[i] ? k : i,
                                      " is open; a periodic box is sheared only between periodic axes");
    }

    // Each tilt within half a period: column k less whole columns i < k, from the nearest axis down.
    bool reduce_tilts() {
        bool reduced = false;
        for (int k = 1; k < dim; ++k)
            for (int i = k - 1; i >= 0; --i) {
                if (!periodic_[i] || !periodic_[k]) continue;
                const double n = std::round(lattice_(i, k) / lattice_(i, i));
                if (n == 0.0) continue;
                lattice_.col(k) -= n * lattice_.col(i);
                reduced = true;
            }
        return reduced;
    }

    void refresh() {
        tilted_ = false;
        for (int k = 0; k < dim; ++k) {
            length_[k] = hi_[k] - lo_[k];
            half_[k] = periodic_[k] ? 0.5 * length_[k] : std::numeric_limits<double>::infinity();
            lattice_(k, k) = length_[k];
            for (int i = 0; i < k; ++i) tilted_ = tilted_ || lattice_(i, k) != 0.0;
            for (int i = k + 1; i < dim; ++i) lattice_(i, k) = 0.0;
        }
        moving_ = !flow_.isZero(0.0);
    }

    V lo_, hi_;
    std::array<bool, dim> periodic_;
    Matrix lattice_ = Matrix::Zero(), flow_ = Matrix::Zero();
    V length_, half_;  // derived from the above by refresh()
    bool tilted_ = false, moving_ = false;
};

}  // namespace micromacro
