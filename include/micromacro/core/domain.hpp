#pragma once
// The simulation box and which of its axes are periodic.
//
// Periodic axes wrap positions into [lo, hi) and measure separations by the minimum image, so a
// pair keeps its identity (and its tangential spring) when one partner crosses the boundary.
// Non-periodic axes are open: particles are held in by walls (or not at all).
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
    double length(int axis) const { return hi_[axis] - lo_[axis]; }

    /// The box mapped by the diagonal deformation x -> F x (a periodic box cannot be sheared).
    Domain deformed(const Eigen::Matrix<double, dim, dim>& F) const {
        if (!any_periodic()) return *this;
        if (!F.isDiagonal(0.0))
            detail::throw_input_error("a periodic box can only be stretched along its axes; the deformation has "
                                      "off-diagonal entries (shear needs Lees-Edwards boundaries, not supported)");
        return Domain(V(F * lo_), V(F * hi_), periodic_);
    }

    /// Separation a - b, shortened to the nearest periodic image on periodic axes.
    MICROMACRO_INLINE V separation(const V& a, const V& b) const {
        V d = a - b;
        // Wrapped positions differ by less than L, so the image is needed only past half a box
        // length: one compare per axis (half_ is infinite on open axes), and the rare case out of
        // line, where its division and library call cannot crowd the pair loop's registers.
        for (int k = 0; k < dim; ++k)
            if (std::abs(d[k]) >= half_[k]) [[unlikely]] d[k] = nearest_image(d[k], k);
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
        for (int k = 0; k < dim; ++k)
            if (periodic_[k] && (x[k] < lo_[k] || x[k] >= hi_[k])) {  // inside: nothing to do (the usual case)
                const double L = hi_[k] - lo_[k];
                x[k] -= L * std::floor((x[k] - lo_[k]) / L);
                if (x[k] >= hi_[k]) x[k] = lo_[k];  // guards the round-off case x = hi
            }
    }

    template <class Archive>
    void serialize(Archive& ar) {
        ar.value(lo_);
        ar.value(hi_);
        ar.value(periodic_);
        refresh();
    }

    /// A periodic axis must be at least two interaction ranges long, otherwise a particle would
    /// meet two images of the same partner and the minimum image would be ambiguous.
    void check_interaction_range(double range) const {
        for (int k = 0; k < dim; ++k)
            if (periodic_[k] && length(k) < 2.0 * range)
                detail::throw_input_error("Domain: periodic axis ", k, " is ", length(k),
                                          " long, shorter than two interaction ranges (2 x ", range, " = ",
                                          2.0 * range, "); enlarge the box or use smaller particles");
    }

private:
    [[gnu::noinline]] double nearest_image(double d, int k) const {
        if (!periodic_[k]) return d;
        // Wrapped positions are less than a period apart: then the image is one period off, and
        // d -+ L is what the rounding below gives, without its division (the pairs across a
        // periodic boundary, a few percent of them, take this path).
        if (std::abs(d) < length_[k]) return d > 0.0 ? d - length_[k] : d + length_[k];
        return d - length_[k] * std::round(d / length_[k]);
    }

    void refresh() {
        for (int k = 0; k < dim; ++k) {
            length_[k] = hi_[k] - lo_[k];
            half_[k] = periodic_[k] ? 0.5 * length_[k] : std::numeric_limits<double>::infinity();
        }
    }

    V lo_, hi_;
    std::array<bool, dim> periodic_;
    V length_, half_;  // derived from the above by refresh()
};

}  // namespace micromacro
