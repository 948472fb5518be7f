// A frictionless scene stores no rotational fields: asking for one must not compile.
// expect-error: exists only in scenes with rotation
#include <micromacro/micromacro.hpp>

int main() {
    micromacro::Simulation<2, micromacro::FrictionlessLinear> sim(
        micromacro::FrictionlessLinear{micromacro::LinearSpringDashpot(1e5, 0.1)});
    return static_cast<int>(sim.particles().get<micromacro::field::AngularVelocity>().size());
}
