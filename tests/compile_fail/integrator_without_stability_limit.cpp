// An integrator must tell the engine its stable time step (stability_limit), besides stepping:
// one without it is refused with the concept's name, not deep in the time-step check.
// expect-error: the integrator does not satisfy TimeIntegrator
#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

struct ForwardEuler {  // steps, but says nothing of its stability
    static constexpr const char* name = "forward-euler";
    static constexpr int order = 1;
    static constexpr bool keeps_previous_forces = false;
    template <class Stages>
    void step(Stages& s, double dt) const {
        s.compute_forces();
        s.kick_drift_kick(0.0, dt, dt);
    }
    template <class Stages>
    void run(Stages& s, double dt, std::size_t steps) const {
        for (std::size_t k = 0; k < steps; ++k) step(s, dt);
    }
};
static_assert(mm::TimeIntegrator<mm::VelocityVerlet> && mm::TimeIntegrator<mm::SymplecticEuler>);
static_assert(!mm::TimeIntegrator<ForwardEuler>);

int main() {
    mm::Simulation<2, mm::FrictionlessLinear, mm::NoWalls, ForwardEuler> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(1e5, 0.1), {}});
    return static_cast<int>(sim.particles().size());
}
