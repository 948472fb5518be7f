#pragma once
// Test-wide helpers: the dimensions every physics test runs in, and random packings.
#include <array>
#include <cmath>
#include <random>
#include <tuple>
#include <type_traits>
#include <vector>

#include <micromacro/micromacro.hpp>

namespace mmtest {

namespace mm = micromacro;

template <int d>
using Dim = std::integral_constant<int, d>;
using Dims = std::tuple<Dim<2>, Dim<3>>;

// The paper's parameters (Sec. 4): density, normal stiffness and damping, mean radius.
inline constexpr double rho = 2000.0, k = 1e5, gamma0 = 0.1, a_mean = 1e-3;

/// The cube [0, L)^dim, periodic on every axis.
template <int dim>
mm::Domain<dim> periodic_box(double L) {
    return mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L));
}

/// Non-overlapping random particles in [0, L]^dim with radii uniform in [a_min, a_max]
/// (random sequential placement; gives up on a particle after many tries).
template <int dim>
struct RandomPacking {
    std::vector<mm::Vec<dim>> x;
    std::vector<double> r;
};

template <int dim>
RandomPacking<dim> random_packing(std::size_t n, double a_min, double a_max, double L, unsigned seed,
                                  bool allow_overlap = false, bool periodic = false) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    RandomPacking<dim> p;
    const mm::Domain<dim> domain = periodic ? periodic_box<dim>(L) : mm::Domain<dim>();
    for (std::size_t tries = 0; p.x.size() < n && tries < 1000 * n; ++tries) {
        const double a = a_min + (a_max - a_min) * U(rng);
        mm::Vec<dim> c;
        for (int k2 = 0; k2 < dim; ++k2) c[k2] = periodic ? L * U(rng) : a + (L - 2 * a) * U(rng);
        bool free = true;
        if (!allow_overlap)
            for (std::size_t j = 0; j < p.x.size() && free; ++j)
                free = domain.separation(c, p.x[j]).norm() > a + p.r[j];
        if (free) {
            p.x.push_back(c);
            p.r.push_back(a);
        }
    }
    return p;
}

}  // namespace mmtest

namespace mmtest {

/// Mean particle volume for radii uniform in [a_min, a_max] (midpoint rule, 1000 bins).
template <int dim>
double mean_particle_volume(double a_min, double a_max) {
    double v = 0.0;
    for (int b = 0; b < 1000; ++b) v += mm::DimTraits<dim>::particle_volume(a_min + (a_max - a_min) * (b + 0.5) / 1000) / 1000;
    return v;
}

/// A dense frictional gas between two walls on the last axis (periodic on the others), n
/// particles with radii 0.5-1.5 mm placed at random (seed), velocities normal with standard
/// deviation `speed` in m/s, dt = t_c / 50 of the smallest pair: contacts open, close, slide and
/// the neighbour lists are rebuilt. Not run yet. Float storage allows coarse positions. `Law`:
/// the paper's frictional law (default) or FrictionlessLinear.
template <int dim, class Real = double, class Integrator = mm::VelocityVerlet, class Law = mm::FrictionalLinear>
auto shaken_walled_packing(std::size_t n, unsigned seed, double speed) {
    const double L = std::pow(n * mean_particle_volume<dim>(0.5e-3, 1.5e-3) / 0.6, 1.0 / dim);
    auto p = random_packing<dim>(n, 0.5e-3, 1.5e-3, L, seed, true, true);
    std::array<bool, dim> periodic;
    for (int a = 0; a < dim; ++a) periodic[a] = a < dim - 1;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(dim - 1, true, 0.0);
    walls.add_axis_aligned(dim - 1, false, L);
    for (auto& x : p.x) x[dim - 1] = 2e-3 + (L - 4e-3) * x[dim - 1] / L;  // inside the walls
    const Law law = [] {
        if constexpr (Law::has_tangential) return Law{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.02, 0.5)};
        else return Law{mm::LinearSpringDashpot(k, gamma0)};
    }();
    mm::BasicSimulation<dim, Real, Law, mm::Walls<dim>, Integrator> sim(
        law, mm::Domain<dim>(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L), periodic), walls);
    if constexpr (std::is_same_v<Real, float>) sim.allow_coarse_positions(true);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> N(0.0, speed);
    for (std::size_t i = 0; i < p.x.size(); ++i) {
        sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
        for (int a = 0; a < dim; ++a) sim.particles().velocity()[i][a] = static_cast<Real>(N(rng));
    }
    sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, 0.5e-3) / 2) / 50);
    return sim;
}

/// A static, confined packing: n paper particles (radii 0.5-1.5 mm, mu = 0.5, restitution 0.3)
/// placed at random with overlaps at volume fraction nu in a cube, then relaxed with background
/// damping until the kinetic energy is below 1e-7 of the elastic energy. `walled_axes` last axes
/// carry two walls each; the others are periodic.
template <int dim>
auto relaxed_simulation(std::size_t n, double nu, unsigned seed, int walled_axes = 1, double mu = 0.5) {
    const double L = std::pow(n * mean_particle_volume<dim>(0.5e-3, 1.5e-3) / nu, 1.0 / dim);
    auto p = random_packing<dim>(n, 0.5e-3, 1.5e-3, L, seed, true, true);
    std::array<bool, dim> periodic;
    for (int a = 0; a < dim; ++a) periodic[a] = a < dim - walled_axes;
    mm::Walls<dim> walls;
    for (int a = dim - walled_axes; a < dim; ++a) {
        walls.add_axis_aligned(a, true, 0.0);
        walls.add_axis_aligned(a, false, L);
        for (std::size_t i = 0; i < p.x.size(); ++i)  // squeeze the centres inside the walls
            p.x[i][a] = p.r[i] + 1e-9 + (L - 2 * p.r[i] - 2e-9) * p.x[i][a] / L;
    }
    const double m = mm::sphere_mass(rho, a_mean);
    const double g0 = mm::damping_for_restitution(k, m / 2, 0.3);
    const double tc = mm::contact_duration(k, g0, m / 2);
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(k, g0),
                                   mu > 0 ? mm::CundallStrack(0.2 * k, 0.2 * g0, mu) : mm::CundallStrack(0.2 * k, 0.0, 0.0)};
    const double gamma_b = 0.1 * m / tc;
    mm::Simulation<dim, mm::FrictionalLinear, mm::Walls<dim>, mm::VelocityVerlet, mm::LinkedCells, mm::BackgroundDamping> sim(
        law, mm::Domain<dim>(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L), periodic), walls, {}, {},
        mm::BackgroundDamping(gamma_b, 0.4 * gamma_b * a_mean * a_mean));
    for (std::size_t i = 0; i < p.x.size(); ++i) sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
    sim.set_time_step(tc / 50);
    sim.prepare();
    for (int chunk = 0; chunk < 400; ++chunk) {
        sim.run(500);
        const auto e = sim.energy();
        if (e.kinetic() < 1e-7 * e.potential()) break;
    }
    return sim;
}

/// A square or simple cubic periodic lattice (16^2 or 7^3) of paper particles (a = 1 mm,
/// frictional) pressed together by `overlap`, each centre jittered by up to 0.2 overlap, in the box
/// [origin, origin + L)^dim, with the particle state stored in Real; dt = t_c/50.
template <int dim, class Real = double>
auto jittered_lattice(double overlap, double origin = 0.0) {
    using V = mm::Vec<dim>;
    const int side = dim == 2 ? 16 : 7;
    const double spacing = 2 * a_mean - overlap, m = mm::sphere_mass(rho, a_mean);
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)};
    const V lo = V::Constant(origin);
    mm::BasicSimulation<dim, Real, mm::FrictionalLinear> sim(law, mm::Domain<dim>::fully_periodic(lo, V(lo + V::Constant(side * spacing))));
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> jitter(-0.2 * overlap, 0.2 * overlap);
    for (int cell = 0; cell < static_cast<int>(std::pow(side, dim)); ++cell) {
        V x;
        for (int a = 0, c = cell; a < dim; ++a, c /= side) x[a] = (c % side + 0.5) * spacing + jitter(rng);
        sim.particles().add(V(x + lo), a_mean, m);
    }
    sim.set_time_step(mm::contact_duration(k, gamma0, m / 2) / 50);
    return sim;
}

template <int dim>
mm::PackingSnapshot<dim> relaxed_packing(std::size_t n, double nu, unsigned seed, int walled_axes = 1, double mu = 0.5) {
    return mm::take_snapshot(relaxed_simulation<dim>(n, nu, seed, walled_axes, mu));
}

}  // namespace mmtest
