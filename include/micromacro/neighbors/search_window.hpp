#pragma once
// Where a neighbour search measures a process's particles along periodic axes they do not span.
// An MPI rank (mpi::DistributedRun) holds a slab of a periodic box: its own particles and the
// ghosts around them, all at their wrapped positions in the whole box, whose minimum image its
// engine measures pairs by, as the serial engine does. A cell grid over the whole periodic axis
// would hold every rank's cells; along an unwrapped axis the search instead maps each position
// into one period [origin, origin + L) and bins them there as along an open axis, the grid then
// spanning the rank's particles only. Pairs come out the same when the particles lie within an
// interval shorter than L less a contact distance, so that no pair within reach straddles the
// window's ends (mpi::DistributedRun unwraps an axis only then).
#include <array>
#include <cstddef>
#include <vector>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"

namespace micromacro {

template <int dim>
struct SearchWindow {
    std::array<bool, dim> unwrap{};      ///< periodic axes searched in the window, as open ones
    std::array<double, dim> origin{};    ///< along such an axis the window is [origin, origin + L)

    bool any() const {
        for (bool u : unwrap)
            if (u) return true;
        return false;
    }

    /// The domain the search measures in: `box` with the unwrapped axes open.
    Domain<dim> search_domain(const Domain<dim>& box) const {
        if (!any()) return box;
        std::array<bool, dim> periodic{};
        for (int a = 0; a < dim; ++a) periodic[a] = box.periodic(a) && !unwrap[a];
        return Domain<dim>(box.lo(), box.hi(), periodic);
    }

    /// The positions `x` of `box` mapped into the window along the unwrapped axes, into `out`:
    /// wrapped into the window as a box of one period wraps them (Domain::wrap).
    template <class Real>
    const std::vector<Vec<dim, Real>>& map(const std::vector<Vec<dim, Real>>& x, const Domain<dim>& box,
                                           std::vector<Vec<dim, Real>>& out) const {
        Vec<dim> lo = box.lo(), hi = box.hi();
        std::array<bool, dim> periodic{};
        for (int a = 0; a < dim; ++a)
            if (unwrap[a] && box.periodic(a)) periodic[a] = true, lo[a] = origin[a], hi[a] = origin[a] + box.length(a);
        const Domain<dim> period(lo, hi, periodic);
        out.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
            Vec<dim> p = convert<double>(x[i]);
            period.wrap(p);
            out[i] = convert<Real>(p);
        }
        return out;
    }
};

}  // namespace micromacro
