// random_packing: a dense random packing of polydisperse particles in a periodic box, prepared by
// the engine and written as a LAMMPS dump, which throughput --packing, analyze_packing and LAMMPS
// (read_dump) read with its box and periodic axes.
//
//   random_packing --dim 2 --particles 1950 --out disks.dump
//   random_packing --dim 3 --particles 13824 --radii 0.5e-3 1.5e-3 --pressure 1e-3 --seed 2 --out spheres.dump
//
// Radii are uniform between the two --radii. The particles are placed at random without overlap at
// a packing fraction of 0.3 (2D) or 0.2 (3D) in a square or cubic periodic box. The box then shrinks
// in affine steps (x -> (1 - e) x, the box with it), 20 time steps apart, while linear contacts with
// a little friction (--mu 0.1) and background damping (Eq. 30) relax the packing: e = 2e-3 while the
// pressure is below 1% of the target, then e proportional to the pressure's shortfall (a box that
// overshoots grows back), none within 2% of the target. It ends within 2% of the pressure with
// the kinetic energy below 1e-3 of the elastic energy. (Frictionless packings creep along their
// soft modes and hardly come to rest; with mu = 0.1 a slow creep remains, about 1e-4 of the
// elastic energy in motion, and the packing is about 0.82 dense in 2D.) The pressure is asked
// for as p / k in 2D and p a / k in 3D, a the mean radius: about the contacts' mean overlap
// relative to a.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "../command_line.hpp"
#include "../standard_output.hpp"

#include <micromacro/io/packing_writer.hpp>
#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

namespace {
struct Options {
    int dim = 2;
    std::size_t particles = 1950;
    std::vector<double> radii{0.5e-3, 1.5e-3};
    double pressure = 5e-4, k = 1e5, kt = 2e4, mu = 0.1, gamma_n = 0.1, density = 2000.0;
    unsigned seed = 1;
    std::string out;
    bool overwrite = false;
};

/// Centres placed at random in the periodic box [0, L)^dim, none overlapping another: random
/// sequential addition, largest particles first, each checked against the particles of its own
/// and the neighbouring cells of a grid a largest diameter wide (against all placed ones in a box
/// under three cells wide). Throws if a particle finds no place in many tries.
template <int dim>
std::vector<mm::Vec<dim>> place(const std::vector<double>& r, double L, std::mt19937_64& rng) {
    const double r_max = *std::max_element(r.begin(), r.end());
    const int cells = static_cast<int>(L / (2.0 * r_max));
    const bool grid_used = cells >= 3;
    const double cell = grid_used ? L / cells : L;
    auto cell_index = [&](std::array<int, dim> c) {
        std::size_t k = 0;
        for (int a = dim - 1; a >= 0; --a) k = k * cells + static_cast<std::size_t>((c[a] % cells + cells) % cells);
        return k;
    };
    std::vector<std::array<int, dim>> neighbours;  // the 3^dim offsets of a cell's neighbourhood
    for (int k = 0; k < (dim == 2 ? 9 : 27); ++k) {
        std::array<int, dim> d;
        for (int a = 0, rest = k; a < dim; ++a, rest /= 3) d[a] = rest % 3 - 1;
        neighbours.push_back(d);
    }
    std::vector<std::vector<std::size_t>> grid(grid_used ? static_cast<std::size_t>(std::pow(cells, dim)) : 1);
    std::vector<std::size_t> order(r.size());
    for (std::size_t i = 0; i < r.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return r[a] > r[b]; });
    std::vector<mm::Vec<dim>> x(r.size());
    std::uniform_real_distribution<double> u(0.0, L);
    auto overlaps = [&](std::size_t i, std::size_t j) {
        mm::Vec<dim> s = x[i] - x[j];
        for (int a = 0; a < dim; ++a) s[a] -= L * std::round(s[a] / L);  // the nearest image
        return s.norm() < r[i] + r[j];
    };
    for (const std::size_t i : order) {
        std::array<int, dim> c{};
        bool free = false;
        for (int attempt = 0; attempt < 100000 && !free; ++attempt) {
            for (int a = 0; a < dim; ++a) {
                x[i][a] = u(rng);
                c[a] = grid_used ? std::min(cells - 1, static_cast<int>(x[i][a] / cell)) : 0;
            }
            free = true;
            if (!grid_used) {
                for (const std::size_t j : grid[0]) free = free && !overlaps(i, j);
                continue;
            }
            for (const auto& d : neighbours) {
                std::array<int, dim> n;
                for (int a = 0; a < dim; ++a) n[a] = c[a] + d[a];
                for (const std::size_t j : grid[cell_index(n)]) free = free && !overlaps(i, j);
            }
        }
        if (!free)
            mm::detail::throw_input_error("particle ", i, " of radius ", r[i], " m found no free place in the start box; "
                                          "use more particles or narrower --radii");
        grid[grid_used ? cell_index(c) : 0].push_back(i);
    }
    return x;
}

struct Measure {
    double mean_overlap = 0.0;  ///< over the contacts, m
    double coordination = 0.0;  ///< contacts per particle, each counted twice
    double pressure = 0.0;      ///< (1 / (dim V)) sum f_n |branch|, N/m in 2D, Pa in 3D
};

template <class Sim>
Measure measure(const Sim& sim) {
    constexpr int dim = Sim::dimension;
    Measure m;
    std::size_t contacts = 0;
    double overlap = 0.0, virial = 0.0;
    sim.for_each_contact([&](const mm::ContactView<dim>& c) {
        ++contacts;
        overlap += c.geometry.overlap;
        virial += c.normal_force * c.branch.norm();
    });
    const auto& box = sim.domain();
    m.mean_overlap = contacts ? overlap / double(contacts) : 0.0;
    m.coordination = 2.0 * double(contacts) / double(sim.particles().size());
    m.pressure = virial / (dim * (box.hi() - box.lo()).prod());
    return m;
}

template <int dim>
int run(const Options& o) {
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<double> radius(o.radii[0], o.radii[1]);
    std::vector<double> r(o.particles);
    double solid = 0.0, mean_r = 0.0, mean_m = 0.0;
    for (double& a : r) {
        a = radius(rng);
        solid += mm::DimTraits<dim>::particle_volume(a);
        mean_r += a / double(o.particles);
        mean_m += mm::sphere_mass(o.density, a) / double(o.particles);
    }
    // The box shrinks to the packing's density, and a periodic box must stay two interaction
    // ranges long (2 x (2 largest radii + the engine's skin)). Random dense packings of radii
    // within a few times of each other stay well below a fraction of 0.95 (2D) and 0.80 (3D) (the
    // default radii: 0.71-0.83 and 0.60-0.61 at the default pressure, up to 80 particles): a box
    // that small even then is refused now, with the count that fits. A wider spread can pack
    // denser; the engine then refuses the compression that would go too far (deform_affinely).
    {
        const double largest = *std::max_element(r.begin(), r.end()), skin = mm::default_skin(r);
        const double range = mm::interaction_range(largest, skin), densest = std::pow(solid / (dim == 2 ? 0.95 : 0.80), 1.0 / dim);
        // The count asked for holds for any draw: radii up to the largest allowed.
        const double enough = std::ceil(o.particles * std::pow(2.0 * mm::interaction_range(o.radii[1], skin) / densest, dim));
        if (densest < 2.0 * range)
            mm::detail::throw_input_error("--particles ", o.particles, " of radii up to ", largest, " m pack into a periodic box of "
                                          "about ", densest, " m, shorter than two interaction ranges (2 x ", range,
                                          " m): a particle would meet two images of one partner; use --particles >= ", enough,
                                          " or radii closer together (--radii)");
    }
    const double start_fraction = dim == 2 ? 0.3 : 0.2;
    const double L = std::pow(solid / start_fraction, 1.0 / dim);
    const std::vector<mm::Vec<dim>> x = place<dim>(r, L, rng);

    const double tc = mm::contact_duration(o.k, o.gamma_n, 0.5 * mean_m);
    const double gamma_b = mean_m / tc;  // a free particle's velocity decays over t_c
    using Law = mm::FrictionalLinear;
    // The lightest spin decays over t_c too (a mean particle's far slower): a stronger rotational
    // drag on a small particle's moment of inertia would be unstable at this step.
    const double r_min = o.radii[0], gamma_r = 0.4 * mm::sphere_mass(o.density, r_min) * r_min * r_min / tc;
    mm::BasicSimulation<dim, double, Law, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::BackgroundDamping> sim(
        Law{mm::LinearSpringDashpot(o.k, o.gamma_n), mm::CundallStrack(o.kt, o.gamma_n, o.mu)},
        mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L)), {}, {}, {},
        mm::BackgroundDamping(gamma_b, gamma_r));
    for (std::size_t i = 0; i < x.size(); ++i) sim.particles().add(x[i], r[i], mm::sphere_mass(o.density, r[i]));
    sim.set_time_step(std::min(tc / 50.0, 0.9 * sim.stable_time_step()));

    const double target = o.pressure * o.k / (dim == 2 ? 1.0 : mean_r);
    const std::size_t step_limit = 2000 * o.particles + 10000000;
    std::size_t steps = 0;
    Measure m = measure(sim);
    for (;;) {
        // Within 2% of the target the box holds still: the work of each step would keep the packing
        // from coming to rest.
        const double shortfall = 1.0 - m.pressure / target;
        const double e = m.pressure < 1e-2 * target    ? 2e-3
                         : std::abs(shortfall) <= 0.02 ? 0.0
                                                       : std::clamp(0.3 * o.pressure * shortfall, -o.pressure, 2e-3);
        if (e != 0.0) sim.deform_affinely(Eigen::Matrix<double, dim, dim>::Identity() * (1.0 - e));
        sim.run(20);
        steps += 20;
        m = measure(sim);
        const auto energy = sim.energy();
        if (std::abs(m.pressure / target - 1.0) <= 0.02 && energy.kinetic() <= 1e-3 * energy.potential()) break;
        if (steps > step_limit)
            mm::detail::throw_input_error("the packing did not come to rest at the pressure within ", steps, " steps (pressure ",
                                          m.pressure / target, " of the target); try a larger --pressure");
    }
    const auto& box = sim.domain();
    const auto& final_x = sim.particles().position();
    const auto& final_r = sim.particles().radius();
    mm::io::write_lammps_dump<dim>(o.out, final_x, final_r, box);
    double fraction = 0.0;
    for (double a : final_r) fraction += mm::DimTraits<dim>::particle_volume(a);
    fraction /= (box.hi() - box.lo()).prod();
    std::printf("%s: %zu particles (radii %.3g-%.3g m, mean %.4g m) in a periodic box of side %.6g m; packing fraction %.4f, "
                "coordination %.3f, mean overlap %.3g of the mean radius, pressure %.4g %s; %zu steps of %.4g s (t_c/%.3g)\n",
                o.out.c_str(), final_x.size(), o.radii[0], o.radii[1], mean_r, box.hi()[0] - box.lo()[0], fraction, m.coordination,
                m.mean_overlap / mean_r, m.pressure, dim == 2 ? "N/m" : "Pa", steps, sim.time_step(), tc / sim.time_step());
    if (!standard_output_complete()) mm::detail::throw_input_error("cannot write the result to standard output (is the disk full?)");
    return 0;
}
}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{"A dense random polydisperse packing in a periodic box, prepared by the engine, written as a LAMMPS dump"};
    app.add_option("--dim", o.dim, "2 or 3")->check(CLI::IsMember({2, 3}))->capture_default_str();
    app.add_option("--particles", o.particles, "how many (at least 4)")->check(CLI::Range(std::size_t{4}, std::size_t{1} << 32))->capture_default_str();
    app.add_option("--radii", o.radii, "smallest and largest radius (m); radii are uniform between them")->expected(2)->capture_default_str();
    app.add_option("--pressure", o.pressure, "the pressure to end at: p / k in 2D, p a / k in 3D (a the mean radius)")
        ->check(micromacro::cli::between(1e-6, 1e-2))
        ->capture_default_str();
    app.add_option("--k", o.k, "normal stiffness (N/m) while preparing")->check(micromacro::cli::positive())->capture_default_str();
    app.add_option("--kt", o.kt, "tangential stiffness (N/m) while preparing")->check(micromacro::cli::positive())->capture_default_str();
    app.add_option("--mu", o.mu, "friction coefficient while preparing (0: frictionless, which may never come to rest)")
        ->check(micromacro::cli::non_negative())
        ->capture_default_str();
    app.add_option("--gamma-n", o.gamma_n, "normal and tangential damping (kg/s) while preparing")->check(micromacro::cli::non_negative())->capture_default_str();
    app.add_option("--density", o.density, "particle density (kg/m^3)")->check(micromacro::cli::positive())->capture_default_str();
    app.add_option("--seed", o.seed, "random seed of the radii and the placement")->capture_default_str();
    app.add_option("--out", o.out, "the LAMMPS dump to write")->required();
    app.add_flag("--overwrite", o.overwrite, "replace --out if it exists");
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);
    try {
        if (!(o.radii[0] > 0.0 && o.radii[1] >= o.radii[0] && std::isfinite(o.radii[1])))
            mm::detail::throw_input_error("--radii ", o.radii[0], " ", o.radii[1], ": give the smallest radius > 0, then the largest (m)");
        if (std::filesystem::exists(o.out) && !o.overwrite)
            mm::detail::throw_input_error("--out ", o.out, " exists; give another name or --overwrite to replace it");
        if (const auto folder = std::filesystem::absolute(o.out).parent_path(); !std::filesystem::is_directory(folder))
            mm::detail::throw_input_error("--out ", o.out, ": the folder ", folder.string(), " does not exist; create it first");
        return o.dim == 2 ? run<2>(o) : run<3>(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "random_packing: %s\n", e.what());
        return 1;
    }
}
