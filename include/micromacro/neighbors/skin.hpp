#pragma once
// The neighbour list's reach: the skin the engine takes when none is set, and how far apart two
// particles can interact with it (the range a periodic box and an MPI halo must hold).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace micromacro {

/// A fifth of the mean radius (1 m without particles), summed in double whatever the storage.
template <class Real>
double default_skin(const std::vector<Real>& radii) {
    double sum = 0.0;
    for (const Real a : radii) sum += double(a);
    return radii.empty() ? 1.0 : 0.2 * sum / double(radii.size());
}

/// The largest centre distance of a candidate pair: the two largest radii's sum bound, plus the skin.
template <class Real>
double interaction_range(const std::vector<Real>& radii, double skin) {
    return radii.empty() ? skin : 2.0 * double(*std::max_element(radii.begin(), radii.end())) + skin;
}

}  // namespace micromacro
