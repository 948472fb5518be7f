// A body force must take what the engine hands it every evaluation (BodyForceStep: the time
// step, the scene's mean flow and the count of particles to act on, which keeps a distributed
// run's ghosts out): one written against another signature is refused with the concept's name
// and the signature it needs, not deep in the engine.
// expect-error: a body force does not satisfy BodyForce
#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

struct Push {  // a user's body force on every particle the engine holds, ghosts included
    template <bool track_energy, int dim, bool rot, class Real>
    void apply(mm::Particles<dim, rot, Real>& p, mm::EnergyBooks&, double) const {
        for (auto& f : p.template get<mm::field::Force>()) f[0] += 1e-6;
    }
};
// The built-in body forces satisfy the concept; Push does not.
static_assert(mm::BodyForce<mm::BackgroundDamping, 2, true, double> && mm::BodyForce<mm::AffineDamping, 3, false, float> &&
              mm::BodyForce<mm::LocalDamping, 2, false, double> && mm::BodyForce<mm::Gravity<3>, 3, true, double>);
static_assert(!mm::BodyForce<Push, 2, true, double> && !mm::BodyForce<mm::Gravity<2>, 3, true, double>);

int main() {
    mm::Simulation<2, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, Push> sim(
        mm::FrictionalLinear{mm::LinearSpringDashpot(1e5, 0.1), mm::CundallStrack(2e4, 0.02, 0.5)}, {}, {}, {}, {}, Push{});
    return static_cast<int>(sim.particles().size());
}
