#pragma once
// The Cartesian split of a box over ranks: dims[a] equal slabs along each axis a, a rank at
// coords inside 0..dims-1 owning the subdomain between its slab boundaries. Geometry only (no
// MPI), so that the ownership rule is one function for every rank and testable without MPI.
//
// Boundaries are lo + (hi - lo) c / dims, computed by one formula wherever they are needed, and a
// coordinate belongs to slab c when boundary(c) <= x < boundary(c + 1): every point has exactly
// one owner, whatever the rounding.
#include <algorithm>
#include <array>
#include <cmath>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/neighbors/search_window.hpp"

namespace micromacro::mpi {

template <int dim>
struct CartesianSplit {
    Vec<dim> lo, hi;                  ///< the whole box
    std::array<bool, dim> periodic{};
    std::array<int, dim> dims{}, coords{};

    static CartesianSplit of(const Domain<dim>& box, const std::array<int, dim>& dims, const std::array<int, dim>& coords) {
        CartesianSplit s{box.lo(), box.hi(), {}, dims, coords};
        for (int a = 0; a < dim; ++a) {
            s.periodic[a] = box.periodic(a);
            if (dims[a] < 1 || coords[a] < 0 || coords[a] >= dims[a])
                micromacro::detail::throw_input_error("CartesianSplit: axis ", a, " has ", dims[a], " slabs and coordinate ", coords[a],
                                          "; give at least one slab and a coordinate in 0..slabs-1");
            if (!(box.hi()[a] > box.lo()[a]))
                micromacro::detail::throw_input_error("CartesianSplit: axis ", a, " of the box is empty (lo = ", box.lo()[a], ", hi = ",
                                          box.hi()[a], "); a split needs a bounded box");
        }
        return s;
    }

    /// The lower boundary of slab c along axis a (c = dims[a]: the box's upper end).
    double boundary(int a, int c) const { return c >= dims[a] ? hi[a] : lo[a] + (hi[a] - lo[a]) * c / dims[a]; }
    double sub_lo(int a) const { return boundary(a, coords[a]); }
    double sub_hi(int a) const { return boundary(a, coords[a] + 1); }

    /// The slab along axis a that holds coordinate x (positions outside the box go to the end
    /// slabs: on an open axis a particle may leave the box).
    int slab(int a, double x) const {
        int c = static_cast<int>(std::floor((x - lo[a]) / (hi[a] - lo[a]) * dims[a]));
        c = std::clamp(c, 0, dims[a] - 1);
        while (c > 0 && x < boundary(a, c)) --c;
        while (c < dims[a] - 1 && x >= boundary(a, c + 1)) ++c;
        return c;
    }

    /// Whether this rank's subdomain owns position x.
    bool owns(const Vec<dim>& x) const {
        for (int a = 0; a < dim; ++a)
            if (slab(a, x[a]) != coords[a]) return false;
        return true;
    }

    /// The window a rank's engine bins its particles in (neighbors/search_window.hpp). The
    /// engine runs in the whole box, where its own particles lie within `drift` of its slab and
    /// its ghosts within `width` (the largest contact distance plus the skin) and `drift` more.
    /// Along a periodic axis of several slabs that span is searched as one period centred on
    /// the slab, so that the cell grid covers the rank's particles and not the whole axis, where
    /// it is shorter than the period less `width` (no pair within reach then straddles the
    /// window's ends); else the whole periodic axis is searched.
    SearchWindow<dim> search_window(double width, double drift) const {
        SearchWindow<dim> w;
        for (int a = 0; a < dim; ++a) {
            const double L = hi[a] - lo[a], slab = sub_hi(a) - sub_lo(a);
            if (!periodic[a] || dims[a] == 1 || !(slab + 2.0 * (width + drift) + width < L)) continue;
            w.unwrap[a] = true;
            w.origin[a] = sub_lo(a) - 0.5 * (L - slab);
        }
        return w;
    }

    /// Refuses a halo wider than one slab along an axis with a neighbour across it: the
    /// exchange passes ghosts one slab on.
    void check_halo(double width) const {
        for (int a = 0; a < dim; ++a) {
            if (dims[a] == 1) continue;
            const double slab_width = (hi[a] - lo[a]) / dims[a];
            if (!(width <= slab_width))
                micromacro::detail::throw_input_error("the halo of ", width, " m (the largest contact distance plus the skin) is wider than the ",
                                          slab_width, " m slabs along axis ", a,
                                          "; use fewer ranks along that axis or a larger box");
        }
    }
};

}  // namespace micromacro::mpi
