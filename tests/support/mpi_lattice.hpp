#pragma once
// The MPI tests' scenes: a dense frictional periodic packing on a jittered lattice, the same on
// every rank, and the lattice in a box of moving walls.
#include <algorithm>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include <micromacro/micromacro.hpp>

#include "support/scenes.hpp"

namespace mmtest {

// A jittered lattice of particles with radii 0.995-1.005 mm, spaced 1.99 mm in a periodic box,
// so that neighbours overlap by up to about 1.5% of a radius; random velocities of 0.2 m/s
// and spins of 40 rad/s. The same on every rank. Rows of particles sit on the box's end and on the
// boundaries between ranks (at multiples of the spacing), a few micrometres either side, so that
// moving a few micrometres takes some of them to another rank.
// `holes`: the fraction of particles given a radius of 0.9 mm instead, out of contact with
// their neighbours, so that some of those around them have too few contacts left (rattlers);
// `spacing` closer than 1.99 mm presses every neighbour pair together.
template <int dim, class Sim>
void fill_lattice(Sim& sim, int per_side, double skin, double holes, double spacing) {
    const double L = per_side * spacing;
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    std::normal_distribution<double> N(0.0, 1.0);
    const int n = dim == 2 ? per_side * per_side : per_side * per_side * per_side;
    for (int k = 0; k < n; ++k) {
        mm::Vec<dim> x;
        int rest = k;
        for (int a = 0; a < dim; ++a) {
            x[a] = (rest % per_side) * spacing + 0.005e-3 * U(rng);  // rows on the ranks' boundaries
            if (x[a] < 0.0) x[a] += L;
            rest /= per_side;
        }
        double r = 1e-3 + 0.005e-3 * U(rng);
        if (holes > 0.0 && 0.5 * (U(rng) + 1.0) < holes) r = 0.9e-3;
        const std::size_t i = sim.particles().add(x, r, mm::sphere_mass(mmtest::rho, r));
        for (int a = 0; a < dim; ++a) sim.particles().velocity()[i][a] = 0.2 * N(rng);
        auto& w = sim.particles().template get<mm::field::AngularVelocity>()[i];
        if constexpr (dim == 2) w = 40.0 * N(rng);
        else w = mm::Vec<3>(40.0 * N(rng), 40.0 * N(rng), 40.0 * N(rng));
    }
    sim.set_time_step(mm::contact_duration(mmtest::k, mmtest::gamma0, mm::sphere_mass(mmtest::rho, 0.995e-3) / 2) / 50);
    sim.set_skin(skin);
    sim.set_auto_sort(false);
}

inline const mm::FrictionalLinear lattice_law{mm::LinearSpringDashpot(mmtest::k, mmtest::gamma0),
                                              mm::CundallStrack(0.2 * mmtest::k, 0.02, 0.5)};

template <int dim>
auto lattice(int per_side, double skin, double holes = 0.0, double spacing = 1.99e-3) {
    mm::BasicSimulation<dim, double, mm::FrictionalLinear> sim(lattice_law, mmtest::periodic_box<dim>(per_side * spacing));
    fill_lattice<dim>(sim, per_side, skin, holes, spacing);
    return sim;
}

// The lattice of 2116 disks or 2197 spheres, enough for the engine to sort them on its own
// (set_auto_sort), numbered at random and eight times as fast (1.6 m/s: partners change within a few
// hundred steps). With `sort_within` = (first, last): sorted and measured, then the measure set so
// that the engine sorts again at a neighbour search after step `first` and by step `last`, and at
// none before (a copy probed first: the candidates' mean index gap moves a little either way from
// search to search; the measure is a quarter of the sum of its largest value before and after).
template <int dim>
auto sorting_lattice(std::optional<std::pair<int, int>> sort_within = std::nullopt) {
    auto scene = lattice<dim>(dim == 2 ? 46 : 13, 10e-6);
    scene.set_auto_sort(true);
    std::vector<mm::Index> random(scene.particles().size());
    std::iota(random.begin(), random.end(), mm::Index{0});
    std::shuffle(random.begin(), random.end(), std::mt19937(5));
    scene.renumber(random);
    for (auto& v : scene.particles().velocity()) v *= 8.0;
    if (!sort_within) return scene;
    scene.prepare();
    auto gap = [](const auto& sim) {  // the engine's own measure of its candidates
        std::vector<mm::IndexPair> pairs;
        sim.visit_pair_histories([&](mm::Index i, mm::Index j, const auto&) { pairs.push_back({i, j}); });
        return mm::mean_index_gap(pairs);
    };
    auto probe = scene;
    double before = gap(probe), within = 0.0;
    for (int step = 1; step <= sort_within->second; ++step) {
        const std::size_t searches = probe.neighbor_rebuilds();
        probe.step();
        if (probe.neighbor_rebuilds() == searches) continue;
        double& largest = step <= sort_within->first ? before : within;
        largest = std::max(largest, gap(probe));
    }
    if (!(within > before)) throw std::logic_error("sorting_lattice: the gap grows at no search in the steps asked for");
    auto search = scene.search_state();
    search.sorted_gap = 0.25 * (before + within);
    scene.restore_search_state(search);
    return scene;
}

// The lattice in a box of walls instead (no periodic axis, an unbounded domain), the outer rows
// pressed 10 um into the walls: along the last axis the upper wall moves in by 20 um over the
// first 200 steps (Eq. 17), along the first axis the upper wall is stress-controlled (Eq. 18) at
// about the pressure of the rows pressed into it, so that it moves; the others are fixed. The
// walls are frictional (the scene's law), so that wall contacts hold springs too; the particles are
// damped against the walls' mean flow (AffineDamping, as in the biaxial test) and pulled down the
// last axis by gravity (too weak to change the motion much: m g is 1e-4 of a contact force, but its
// potential energy is 1-3% of the total, which a rank counting its ghosts' would change). `bounded`: the
// domain (open on every axis) spans the outer rows' centres, so that the rows sit on the
// boundaries between slabs and the outer ones half outside; else it is unbounded, as the biaxial
// test's.
template <int dim>
auto walled_lattice(int per_side, double skin, bool bounded) {
    const double spacing = 1.99e-3, press = 10e-6, lo = -1e-3 + press, hi = (per_side - 1) * spacing + 1e-3 - press;
    mm::Walls<dim> walls;
    walls.add_box(mm::Vec<dim>::Constant(lo), mm::Vec<dim>::Constant(hi));
    const mm::Domain<dim> domain =
        bounded ? mm::Domain<dim>(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant((per_side - 1) * spacing), {}) : mm::Domain<dim>();
    const double gamma = 1e-3;  // kg/s: changes the velocities by about 1e-2 over 200 steps
    mm::Gravity<dim> gravity;
    gravity.g[dim - 1] = -9.81;
    mm::BasicSimulation<dim, double, mm::FrictionalLinear, mm::Walls<dim>, mm::VelocityVerlet, mm::LinkedCells, mm::AffineDamping,
                        mm::Gravity<dim>>
        sim(lattice_law, domain, walls, {}, {}, mm::AffineDamping(gamma, 0.4 * gamma * 1e-6), gravity);
    fill_lattice<dim>(sim, per_side, skin, 0.0, spacing);
    for (auto& x : sim.particles().position())  // the periodic lattice's wrapped jitter back next to its row
        for (int a = 0; a < dim; ++a)
            if (x[a] > hi - 0.5e-3) x[a] -= per_side * spacing;
    const double dt = sim.time_step(), m = mm::sphere_mass(mmtest::rho, 1e-3);
    sim.walls()[2 * dim - 1].motion = mm::StrainControlled{20e-6, 400 * dt};
    const double side = hi - lo, area = dim == 2 ? side : side * side;
    sim.walls()[1].motion = mm::StressControlled{mmtest::k * press * per_side / area * (dim == 2 ? 1 : per_side), 20 * m, 0.0};
    return sim;
}

}  // namespace mmtest
