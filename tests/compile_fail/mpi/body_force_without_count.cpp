// A body force whose apply takes no count of particles would act on a rank's ghosts too, whose
// owners apply it, and book their energy twice: a distributed run of it must not compile.
// expect-error: every body force's apply must take the count of particles
#include <micromacro/micromacro.hpp>
#include <micromacro/mpi/distributed_run.hpp>

namespace mm = micromacro;

struct Push {  // a user's body force without a count: it acts on every particle the engine holds
    template <bool track_energy, int dim, bool rot, class Real>
    void apply(mm::Particles<dim, rot, Real>& p, mm::EnergyBooks&, double) const {
        for (auto& f : p.template get<mm::field::Force>()) f[0] += 1e-6;
    }
};
using Scene = mm::Simulation<2, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::BackgroundDamping, Push>;
// The built-in policies take a count; Push does not.
static_assert(mm::mpi::ActsOnACount<mm::BackgroundDamping, Scene> && mm::mpi::ActsOnACount<mm::AffineDamping, Scene> &&
              mm::mpi::ActsOnACount<mm::LocalDamping, Scene> && mm::mpi::ActsOnACount<mm::Gravity<2>, Scene>);
static_assert(!mm::mpi::ActsOnACount<Push, Scene>);

int main() {
    const Scene whole(mm::FrictionalLinear{mm::LinearSpringDashpot(1e5, 0.1), mm::CundallStrack(2e4, 0.02, 0.5)}, {}, {}, {}, {},
                      mm::BackgroundDamping(), Push{});
    mm::mpi::DistributedRun<Scene> run(MPI_COMM_WORLD, whole);
    return static_cast<int>(run.owned());
}
