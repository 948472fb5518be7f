#pragma once
// Where an average is taken (an axis-aligned box) and which contacts it counts.
#include <cmath>

#include "micromacro/averaging/snapshot.hpp"

namespace micromacro {

/// Which contacts and particles belong to an averaging volume.
enum class SelectionRule {
    contact_point,   ///< Eq. 31 (the paper's choice in Sec. 4.4): a contact counts if its contact point is inside
    particle_centre  ///< Eq. 10 and 13: each partner whose centre is inside brings its share of the contact
};

template <int dim>
struct Region {
    Vec<dim> lo, hi;

    /// The whole packing (see PackingSnapshot::bounds).
    static Region whole(const PackingSnapshot<dim>& s) {
        const auto [lo, hi] = s.bounds();
        return {lo, hi};
    }
    /// The packing without a layer of `margin` times its extent next to each non-periodic
    /// boundary (the paper leaves out 10% next to each wall).
    static Region inner(const PackingSnapshot<dim>& s, double margin = 0.1) { return whole(s).inner(s.domain, margin); }

    /// This region without a layer of `margin` times its extent next to each non-periodic boundary.
    Region inner(const Domain<dim>& domain, double margin) const {
        if (!(margin >= 0.0 && margin < 0.5))
            detail::throw_input_error("averaging margin = ", margin, " must be in [0, 0.5): it is the fraction of the box "
                                      "left out next to each wall");
        Region r = *this;
        for (int a = 0; a < dim; ++a) {
            if (domain.periodic(a)) continue;
            const double cut = margin * (r.hi[a] - r.lo[a]);
            r.lo[a] += cut;
            r.hi[a] -= cut;
        }
        return r;
    }
    /// Any box.
    static Region box(const Vec<dim>& lo, const Vec<dim>& hi) {
        for (int a = 0; a < dim; ++a)
            if (!(hi[a] > lo[a]) || !std::isfinite(lo[a]) || !std::isfinite(hi[a]))
                detail::throw_input_error("averaging box: axis ", a, " has lo = ", lo[a], " and hi = ", hi[a], "; need hi > lo");
        return {lo, hi};
    }

    double volume() const { return (hi - lo).prod(); }
    /// Closed box: a wall contact lies exactly on the boundary of the whole region and must count.
    /// (Wrapped periodic points never reach hi, so a periodic contact is not counted twice.)
    bool contains(const Vec<dim>& x) const {
        for (int a = 0; a < dim; ++a)
            if (!(x[a] >= lo[a] && x[a] <= hi[a])) return false;
        return true;
    }
};

}  // namespace micromacro
