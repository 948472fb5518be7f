// Example 03: an element test of your own. 400 frictional disks in a periodic cell are
// compressed isotropically to a pressure p by a stress servo, then sheared (simple shear,
// x moving with y) at constant p: sigma_yy servo-controlled, the cell's length along x held.
// Prints the shear strain, stress ratio -sigma_xy / sigma_yy, pressure, volume fraction and
// coordination as the packing goes from its isotropic state towards steady shearing.
//
// Usage: 03_element_test [GAIN]   GAIN: the shear stage's servo gain as the stress error, in units of
// 1/GAIN of p, that asks for the largest rate (default 10). Exit status 0 when the servo held
// sigma_yy within 1% of p while shearing, 1 when it did not, for a bad argument or an error.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <micromacro/micromacro.hpp>

namespace mm = micromacro;
using V = mm::Vec<2>;

int main(int argc, char** argv) try {
    double gain = 10;
    if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
        std::printf("03_element_test: a periodic cell of 400 disks compressed to 1 kPa, then sheared at constant sigma_yy\n"
                    "usage: 03_element_test [GAIN]   (the shear servo's gain: a stress error of p / GAIN asks for the\n"
                    "largest rate; default 10, at least 1)\n");
        return 0;
    }
    if (argc > 2 || (argc == 2 && !(std::sscanf(argv[1], "%lf", &gain) == 1 && gain >= 1 && std::isfinite(gain)))) {
        std::fprintf(stderr, "03_element_test: '%s' is not a gain; give one number >= 1 (default 10), see --help\n", argv[argc - 1]);
        return 1;
    }
    const double rho = 2000, k = 1e5, gamma0 = 0.1, p = 1000;  // kg/m^3, N/m, kg/s, N/m (2D stress)
    // The packing: radii 0.5-1 mm on a jittered square grid, a loose gas at rest.
    const int side = 20;
    const double spacing = 2.2e-3;
    mm::Domain<2> cell = mm::Domain<2>::fully_periodic(V::Zero(), V::Constant(side * spacing));
    const double tc = mm::contact_duration(k, gamma0, mm::sphere_mass(rho, 0.5e-3) / 2);
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)};
    // Drag against the cell's own flow: it calms the packing without resisting the deformation.
    mm::Simulation<2, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::AffineDamping> sim(
        law, cell, {}, {}, {}, mm::AffineDamping(mm::sphere_mass(rho, 0.75e-3) / (20 * tc), 0.0));
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> radius(0.5e-3, 1e-3), jitter(-0.05e-3, 0.05e-3);
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j) {
            const double a = radius(rng);
            sim.particles().add(V((i + 0.5) * spacing + jitter(rng), (j + 0.5) * spacing + jitter(rng)), a, mm::sphere_mass(rho, a));
        }
    sim.set_time_step(tc / 50);

    // Stage 1: every normal stress to p, the shear stress to zero. The servo's gain: a 25% stress
    // error asks for the largest rate.
    const double max_rate = 50;  // 1/s
    mm::CellControl<2> compress(4 * max_rate / p, max_rate);
    compress.pressure(p);
    while (true) {
        compress.run(sim, 5000);
        const auto m = compress.measure(sim);
        if (std::abs(m.pressure / p - 1) < 1e-3 && m.stress_kinetic.norm() < 1e-6 * p) break;
    }
    std::printf("isotropic: p = %.1f N/m, volume fraction %.4f, coordination %.2f\n", compress.measure(sim).pressure,
                compress.measure(sim).volume_fraction, compress.measure(sim).coordination);

    // Stage 2: simple shear at 20 /s to a strain of 0.3, sigma_yy held at p (by default a 10% error
    // asks for the largest rate: the proportional servo's lag, rate / gain, is a fraction of a
    // percent), the length along x fixed.
    mm::CellControl<2> shear(gain * max_rate / p, max_rate);
    shear.rate(0, 1, 20.0).stress(1, 1, p).hold(0, 0);
    std::printf("%8s %12s %12s %10s %8s\n", "gamma", "-s_xy/s_yy", "p (N/m)", "phi", "Z");
    double worst = 0;
    const auto rows = std::size_t(std::lround(0.02 / (20.0 * sim.time_step())));  // a row every 0.02 of strain
    for (int row = 0; row < 15; ++row) {
        shear.run(sim, rows);
        const auto m = shear.measure(sim);
        const double sxy = 0.5 * (m.stress(0, 1) + m.stress(1, 0));
        worst = std::max(worst, std::abs(m.stress(1, 1) / p - 1));
        std::printf("%8.3f %12.4f %12.1f %10.4f %8.2f\n", shear.deformation()(0, 1), -sxy / m.stress(1, 1), m.pressure,
                    m.volume_fraction, m.coordination);
    }
    std::printf("sigma_yy within %.2f%% of p while shearing\n", 100 * worst);
    return worst < 0.01 ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "03_element_test: %s\n", e.what());
    return 1;
}
