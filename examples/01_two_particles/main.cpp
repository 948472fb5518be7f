// Example 01: two particles collide head-on. Prints the measured contact duration and
// restitution next to the prediction of Eq. 22, in 2D and 3D, for the paper's parameters
// (two particles of the mean radius 1 mm, rho = 2000 kg/m^3, k = 1e5 N/m, gamma_0 = 0.1 kg/s).
//
// Usage: 01_two_particles [steps_per_contact]   (default 200: dt = t_c / 200)
// Exit status: 0 when both dimensions match Eq. 22 to 1e-3 relative, 1 when one misses it, 2 for a
// bad argument or an error.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

template <int dim>
bool report(double steps_per_contact) {
    const double a = 1e-3, rho = 2000.0, k = 1e5, gamma0 = 0.1;
    const double m = mm::sphere_mass(rho, a);
    const double m12 = mm::reduced_mass(m, m);
    const double tc = mm::contact_duration(k, gamma0, m12);
    const double e = mm::restitution(k, gamma0, m12);
    const double dt = tc / steps_per_contact;
    const auto measured = mm::measure_normal_collision<dim>(mm::LinearSpringDashpot(k, gamma0), m, a, m, a, 0.1, dt);
    const double err_tc = std::abs(measured.contact_duration / tc - 1.0);
    const double err_e = std::abs(measured.restitution / e - 1.0);
    std::printf("%dD  dt = t_c/%g = %.4g s\n", dim, steps_per_contact, dt);
    std::printf("    contact duration  predicted %.6e s  measured %.6e s  relative error %.2e\n", tc,
                measured.contact_duration, err_tc);
    std::printf("    restitution       predicted %.6f    measured %.6f    relative error %.2e\n", e,
                measured.restitution, err_e);
    return err_tc < 1e-3 && err_e < 1e-3;
}

int main(int argc, char** argv) {
    double steps_per_contact = 200.0;
    if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
        std::printf("01_two_particles: a head-on collision of two 1 mm particles against Eq. 22, in 2D and 3D\n"
                    "usage: 01_two_particles [STEPS_PER_CONTACT]   (dt = t_c / STEPS_PER_CONTACT, default 200, at least 10)\n"
                    "exit status: 0 both match Eq. 22 to 1e-3, 1 a mismatch, a bad argument or an error (the message says which)\n");
        return 0;
    }
    if (argc > 2) {
        std::fprintf(stderr, "01_two_particles: %d arguments given, at most one (steps per contact); see --help\n", argc - 1);
        return 1;
    }
    if (argc > 1) {
        char* end = nullptr;
        steps_per_contact = std::strtod(argv[1], &end);
        if (end == argv[1] || *end != '\0' || !(steps_per_contact >= 10.0)) {
            std::fprintf(stderr, "01_two_particles: steps per contact '%s' is invalid; give a number >= 10\n", argv[1]);
            return 1;
        }
    }
    try {
        const bool ok_2d = report<2>(steps_per_contact), ok_3d = report<3>(steps_per_contact);  // both reported
        const bool ok = ok_2d && ok_3d;
        std::printf(ok ? "both match Eq. 22 to 1e-3\n" : "MISMATCH with Eq. 22 beyond 1e-3\n");
        return ok ? 0 : 1;
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "01_two_particles: %s\n", ex.what());
        return 1;
    }
}
