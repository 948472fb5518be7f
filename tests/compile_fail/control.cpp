// Control for the compile-fail tests (no expect-error line): the same set-up used correctly compiles. If this "fails to
// fail", the harness itself (include paths, flags) is broken and the other results mean nothing.
#include <micromacro/micromacro.hpp>

int main() {
    micromacro::Simulation<2, micromacro::FrictionalLinear> sim(
        micromacro::FrictionalLinear{micromacro::LinearSpringDashpot(1e5, 0.1), micromacro::CundallStrack(2e4, 0.02, 0.5)});
    return static_cast<int>(sim.particles().get<micromacro::field::AngularVelocity>().size());
}
