// Friction without rotation keeps the tangential springs but stores no rotational fields: asking
// for one must not compile.
// expect-error: exists only in scenes with rotation
#include <micromacro/micromacro.hpp>

int main() {
    namespace mm = micromacro;
    mm::Simulation<3, mm::FrictionalLinearWithoutRotation> sim(mm::FrictionalLinearWithoutRotation{
        mm::LinearSpringDashpot(1e5, 0.1), mm::CundallStrackWithoutRotation(2e4, 0.02, 0.5)});
    return static_cast<int>(sim.particles().get<micromacro::field::Torque>().size());
}
