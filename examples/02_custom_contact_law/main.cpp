// Example 02: a contact law of one's own (walton_braun.hpp, written outside the library) run by
// the engine unchanged. Two particles collide head-on at three speeds, in 2D and 3D; the program
// prints the measured restitution and overlap duration next to the law's closed forms: e =
// sqrt(k1/k2), and the time the surfaces overlap, the force's duration (pi/2) (sqrt(m*/k1) +
// sqrt(m*/k2)) plus the drift from the plastic overlap delta_0 = (1 - e^2) v sqrt(m*/k1), where
// the force ends, to zero at the speed e v: (1/e - e) sqrt(m*/k1).
//
// Usage: 02_custom_contact_law   (dt = t_c / 200)
// Exit status: 0 when every collision matches the closed forms to 1e-3 relative, 1 when one
// misses, 2 for an argument (it takes none) or an error.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "walton_braun.hpp"

namespace mm = micromacro;

template <int dim>
bool report() {
    const double a = 1e-3, rho = 2000.0, k1 = 5e4, k2 = 2e5;
    const double m = mm::sphere_mass(rho, a), m12 = m / 2;
    const double e = std::sqrt(k1 / k2);
    const double tc = std::numbers::pi / 2 * (std::sqrt(m12 / k1) + std::sqrt(m12 / k2)) + (1.0 / e - e) * std::sqrt(m12 / k1);
    bool ok = true;
    for (double v : {0.01, 0.1, 1.0}) {
        const auto c = mm::measure_normal_collision<dim>(example::WaltonBraun(k1, k2), m, a, m, a, v, tc / 200);
        const double err_tc = std::abs(c.contact_duration / tc - 1.0), err_e = std::abs(c.restitution / e - 1.0);
        std::printf("%dD  v = %4.2f m/s  overlap %.6e s (closed form %.6e, error %.1e)  e %.6f (closed form %.6f, error %.1e)\n",
                    dim, v, c.contact_duration, tc, err_tc, c.restitution, e, err_e);
        ok = ok && err_tc < 1e-3 && err_e < 1e-3;
    }
    return ok;
}

int main(int argc, char** argv) {
    if (argc > 1) {
        if (std::string(argv[1]) != "--help" && std::string(argv[1]) != "-h") {
            std::fprintf(stderr, "02_custom_contact_law: it takes no arguments, '%s' given; see --help\n", argv[1]);
            return 1;
        }
        std::printf("02_custom_contact_law: a user's contact law (examples/02_custom_contact_law/walton_braun.hpp) "
                    "against its closed forms, in 2D and 3D\nusage: 02_custom_contact_law   (no arguments)\n"
                    "exit status: 0 all match to 1e-3, 1 a mismatch, an argument or an error (the message says which)\n");
        return 0;
    }
    try {
        const bool ok_2d = report<2>(), ok_3d = report<3>();  // both reported
        const bool ok = ok_2d && ok_3d;
        std::printf(ok ? "every collision matches the closed forms to 1e-3\n" : "MISMATCH with the closed forms beyond 1e-3\n");
        return ok ? 0 : 1;
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "02_custom_contact_law: %s\n", ex.what());
        return 1;
    }
}
