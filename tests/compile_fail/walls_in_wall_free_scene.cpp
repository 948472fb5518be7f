// A scene built without walls has no wall code: using walls must not compile.
// expect-error: NoWalls.*has no member named.*size
#include <micromacro/micromacro.hpp>

int main() {
    micromacro::Simulation<2, micromacro::FrictionlessLinear> sim(
        micromacro::FrictionlessLinear{micromacro::LinearSpringDashpot(1e5, 0.1)});
    return static_cast<int>(sim.walls().size());
}
