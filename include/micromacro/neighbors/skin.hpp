#pragma once
// The neighbour list's reach: the skin the engine takes when none is set, and how far apart two
// particles can interact with it (the range a periodic box and an MPI halo must hold).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace micromacro {

/// A fifth of the mean radius of `count` radii summing to `radius_sum` (1 m without particles).
inline double default_skin(double radius_sum, double count) { return count > 0 ? 0.2 * radius_sum / count : 1.0; }
/// The same for a scene's radii, summed in double whatever the storage.
template <class Real>
double default_skin(const std::vector<Real>& radii) {
    double sum = 0.0;
    for (const Real a : radii) sum += double(a);
    return default_skin(sum, double(radii.size()));
}

/// The largest centre distance of a candidate pair: the two largest radii's sum bound (twice the
/// largest radius, 0 without particles), plus the skin.
inline double interaction_range(double largest_radius, double skin) { return 2.0 * largest_radius + skin; }
template <class Real>
double interaction_range(const std::vector<Real>& radii, double skin) {
    return radii.empty() ? skin : interaction_range(double(*std::max_element(radii.begin(), radii.end())), skin);
}

}  // namespace micromacro
