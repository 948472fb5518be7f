#pragma once
// The Cartesian split of a box over ranks: dims[a] slabs along each axis a, a rank at coords
// inside 0..dims-1 owning the subdomain between its slab boundaries. Geometry only (no MPI), so
// that the ownership rule is one function for every rank and testable without MPI.
//
// Boundaries are lo + (hi - lo) c / dims (equal slabs), or lo + (hi - lo) f_c with the fractions
// f_c of `cuts` (slabs that hold equal shares of the particles, balanced_cuts), computed by one
// formula wherever they are needed, and a coordinate belongs to slab c when boundary(c) <= x <
// boundary(c + 1): every point has exactly one owner, whatever the rounding.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

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
    /// Along each axis the inner boundaries 1..dims-1 as rising fractions of the box; empty:
    /// equal slabs.
    std::array<std::vector<double>, dim> cuts{};

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
    double boundary(int a, int c) const {
        if (c >= dims[a]) return hi[a];
        if (c <= 0 || cuts[a].empty()) return lo[a] + (hi[a] - lo[a]) * c / dims[a];
        return lo[a] + (hi[a] - lo[a]) * cuts[a][static_cast<std::size_t>(c - 1)];
    }
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

    /// Cuts along axis a that leave equal shares of `counts`, a histogram of the particles over
    /// equal bins of [lo, hi] along a, in the slabs (by linear interpolation within a bin), as
    /// fractions for `cuts`. Each cut stays a halo `width` inside the present boundaries on its
    /// either side, and a width above the cut below it: so a slab stays at least a halo wide,
    /// and a particle that moves less than a halo width goes at most one slab on, as the
    /// exchanges between neighbouring ranks need. The present slabs must be a halo wide
    /// (check_halo, refused with its message): else a cut would have no room between its bounds.
    std::vector<double> balanced_cuts(int a, const std::vector<double>& counts, double width) const {
        check_halo(width);
        double total = 0.0;
        for (double c : counts) total += c;
        const double L = hi[a] - lo[a], bin = L / double(counts.size());
        std::vector<double> cut;
        double below = 0.0, previous = lo[a];
        std::size_t k = 0;
        for (int c = 1; c < dims[a]; ++c) {
            const double share = total * c / dims[a];
            while (k < counts.size() && below + counts[k] < share) below += counts[k++];
            double x = boundary(a, c);
            if (total > 0.0 && k < counts.size())
                x = lo[a] + bin * (double(k) + (counts[k] > 0.0 ? (share - below) / counts[k] : 0.0));
            x = std::clamp(x, std::max(boundary(a, c - 1), previous) + width, boundary(a, c + 1) - width);
            cut.push_back((x - lo[a]) / L);
            previous = x;
        }
        return cut;
    }

    /// Refuses a halo wider than one slab along an axis with a neighbour across it: the
    /// exchange passes ghosts one slab on.
    void check_halo(double width) const {
        for (int a = 0; a < dim; ++a) {
            if (dims[a] == 1) continue;
            double slab_width = hi[a] - lo[a];
            for (int c = 0; c < dims[a]; ++c) slab_width = std::min(slab_width, boundary(a, c + 1) - boundary(a, c));
            if (!(width <= slab_width))
                micromacro::detail::throw_input_error("the halo of ", width, " m (the largest contact distance plus the skin) is wider than the ",
                                          slab_width, " m slabs along axis ", a,
                                          "; use fewer ranks along that axis or a larger box");
        }
    }
};

}  // namespace micromacro::mpi
