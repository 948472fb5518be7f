#pragma once
// What the averaging works on: a frozen packing with its contacts and their forces, taken from a
// running simulation (engine/snapshot.hpp) or built from a packing file (io/detected_contacts.hpp).
// Averages never touch the engine, so a packing made by any code can be analysed the same way.
#include <algorithm>
#include <limits>
#include <optional>
#include <vector>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/index.hpp"

namespace micromacro {

/// One contact. Conventions as everywhere: n points from j to i, forces act on i, overlap > 0.
template <int dim>
struct ContactRecord {
    Index i = 0, j = 0;
    bool wall = false;             ///< j is a wall number
    Vec<dim> normal;               ///< from j to i
    Vec<dim> branch;               ///< r_i - r_j (minimum image); for a wall, r_i minus its projection on the plane
    Vec<dim> point;                ///< contact point (midpoint of the overlap; on the plane for a wall), wrapped
    double share_i = 1.0;          ///< |r_i - point| / |branch|: i's part of the branch (1 for a wall)
    double overlap = 0.0;
    double normal_force = 0.0;     ///< along n, positive = compressive
    Vec<dim> tangential_force = Vec<dim>::Zero();
    double k = 0.0, kt = 0.0;      ///< the contact's normal and tangential stiffness
    bool sliding = false;          ///< at the Coulomb limit
    Vec<dim> force() const { return normal_force * normal + tangential_force; }
};

/// A planar wall as the averages see it.
template <int dim>
struct WallRecord {
    Vec<dim> normal;  ///< into the domain
    double offset;    ///< plane normal . x = offset
    Vec<dim> force;   ///< on the wall from the particles
    int axis() const { return aligned_axis<dim>(normal); }
    double coordinate() const { return normal[axis()] > 0 ? offset : -offset; }
};

template <int dim>
struct PackingSnapshot {
    Domain<dim> domain;
    std::vector<Vec<dim>> position, velocity;  ///< velocity may be empty
    std::vector<double> radius, mass;          ///< mass may be empty
    std::vector<ContactRecord<dim>> contacts;
    std::vector<WallRecord<dim>> walls;

    std::size_t size() const { return position.size(); }

    /// The extent of the packing per axis: the periodic box, else the two walls facing each other
    /// on that axis, else the particles' bounding box (surfaces included).
    std::pair<Vec<dim>, Vec<dim>> bounds() const {
        Vec<dim> lo, hi;
        for (int a = 0; a < dim; ++a) {
            if (domain.periodic(a)) {
                lo[a] = domain.lo()[a];
                hi[a] = domain.hi()[a];
                continue;
            }
            std::optional<double> wl, wh;
            for (const auto& w : walls)
                if (w.axis() == a) (w.normal[a] > 0 ? wl : wh) = w.coordinate();
            double pl = std::numeric_limits<double>::infinity(), ph = -pl;
            for (std::size_t p = 0; p < size(); ++p) {
                pl = std::min(pl, position[p][a] - radius[p]);
                ph = std::max(ph, position[p][a] + radius[p]);
            }
            lo[a] = wl.value_or(pl);
            hi[a] = wh.value_or(ph);
        }
        return {lo, hi};
    }
};

namespace detail {
template <int dim>
ContactRecord<dim> pair_record(Index i, Index j, const Vec<dim>& ri, double ai, double aj, const Vec<dim>& branch,
                               const Domain<dim>& domain) {
    ContactRecord<dim> c;
    c.i = i;
    c.j = j;
    const double dist = branch.norm();
    c.normal = branch / dist;
    c.branch = branch;
    c.overlap = ai + aj - dist;
    const double to_point = ai - 0.5 * c.overlap;  // the contact point halves the overlap
    c.share_i = to_point / dist;
    c.point = ri - to_point * c.normal;
    domain.wrap(c.point);
    return c;
}
}  // namespace detail

}  // namespace micromacro
