// A neighbour search must measure pairs in the scene's domain (periodic images, a sheared cell):
// one whose find_pairs takes no Domain is refused with the concept's name.
// expect-error: the neighbour search does not satisfy NeighborSearch
#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

struct OpenSpaceSearch {  // every pair by plain distance: wrong in any periodic box
    template <int dim, class Real>
    void find_pairs(const std::vector<mm::Vec<dim, Real>>& x, const std::vector<Real>& r, double skin,
                    std::vector<mm::IndexPair>& out) const {
        for (mm::Index i = 0; i < x.size(); ++i)
            for (mm::Index j = i + 1; j < x.size(); ++j)
                if ((x[i] - x[j]).norm() < r[i] + r[j] + skin) out.push_back({i, j});
    }
};
static_assert(mm::NeighborSearch<mm::LinkedCells, 3, double> && mm::NeighborSearch<mm::BruteForce, 2, float>);
static_assert(!mm::NeighborSearch<OpenSpaceSearch, 2, double>);

int main() {
    mm::Simulation<2, mm::FrictionlessLinear, mm::NoWalls, mm::VelocityVerlet, OpenSpaceSearch> sim(
        mm::FrictionlessLinear{mm::LinearSpringDashpot(1e5, 0.1), {}});
    return static_cast<int>(sim.particles().size());
}
