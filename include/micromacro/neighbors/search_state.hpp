#pragma once
// What a scene's next neighbour search waits on and decides by: where the last search found the
// particles and the walls (a search follows once one has moved half the skin), and the order's
// measure at the last sort (neighbors/spatial_order.hpp). A scene assembled elsewhere takes it
// over (BasicSimulation::restore_search_state), so that its searches and sorts fall where the
// original's would: mpi::DistributedRun's ranks and the scene mpi::whole_scene gathers.
#include <vector>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/neighbors/spatial_order.hpp"

namespace micromacro {

template <int dim, class Real = double>
struct SearchState {
    std::vector<Vec<dim, Real>> particles;  ///< positions at the last search, by index
    std::vector<double> walls;              ///< the walls' offsets then
    /// The candidates' mean index gap the last sort left; 0: never sorted; negative: sorted
    /// since the last search, which measures it (order_action).
    double sorted_gap = 0.0;
};

}  // namespace micromacro
