#pragma once
// The contacts of a packing that comes without them (a file of positions and radii): every
// overlapping pair, found by a neighbour search, with a linear normal force, as the averages
// need them.
#include <algorithm>
#include <cmath>
#include <vector>

#include "micromacro/averaging/snapshot.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/neighbors/linked_cells.hpp"

namespace micromacro {

/// Finds the contacts of a packing given only positions and radii (overlap > 0) and gives them
/// linear forces: f_n = k overlap, no tangential force, stiffnesses k and kt for the stiffness
/// tensor. Wall contacts are not searched (a file packing has no walls).
template <int dim>
void detect_contacts(PackingSnapshot<dim>& s, double k, double kt) {
    detail::require_positive(k, "k", "give the normal contact stiffness in N/m");
    detail::require_non_negative(kt, "kt", "use 0 for frictionless contacts");
    for (std::size_t p = 0; p < s.size(); ++p) {
        for (int a = 0; a < dim; ++a)
            if (!std::isfinite(s.position[p][a]))
                detail::throw_input_error("particle ", p, ": position component ", a, " = ", s.position[p][a], " is not finite");
        if (!(s.radius[p] > 0.0) || !std::isfinite(s.radius[p]))
            detail::throw_input_error("particle ", p, ": radius = ", s.radius[p], " is invalid: it must be finite and > 0");
    }
    if (!s.radius.empty()) s.domain.check_interaction_range(2.0 * *std::max_element(s.radius.begin(), s.radius.end()));
    std::vector<IndexPair> pairs;
    LinkedCells().find_pairs(s.position, s.radius, s.domain, 0.0, pairs);
    s.contacts.clear();
    for (const auto [i, j] : pairs) {
        const Vec<dim> branch = s.domain.separation(s.position[i], s.position[j]);
        if (branch.squaredNorm() == 0.0)
            detail::throw_input_error("particles ", i, " and ", j, " have coincident centres; the contact normal is undefined");
        auto c = detail::pair_record<dim>(i, j, s.position[i], s.radius[i], s.radius[j], branch, s.domain);
        c.normal_force = k * c.overlap;
        c.k = k;
        c.kt = kt;
        s.contacts.push_back(c);
    }
}

}  // namespace micromacro
