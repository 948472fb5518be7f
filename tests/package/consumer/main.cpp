// Uses the library the way a user would: one umbrella header, one collision, checked against Eq. 22.
#include <cmath>
#include <cstdio>

#include <micromacro/micromacro.hpp>

int main() {
    namespace mm = micromacro;
    const double m = mm::sphere_mass(2000.0, 1e-3);
    const double tc = mm::contact_duration(1e5, 0.1, m / 2);
    const auto r = mm::measure_normal_collision<3>(mm::LinearSpringDashpot(1e5, 0.1), m, 1e-3, m, 1e-3, 0.1, tc / 100);
    std::printf("t_c measured %g predicted %g\n", r.contact_duration, tc);
    return std::abs(r.contact_duration / tc - 1.0) < 1e-2 ? 0 : 1;
}
