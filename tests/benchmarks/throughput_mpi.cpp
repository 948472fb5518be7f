// throughput_mpi: the serial engine over MPI ranks (mpi::DistributedRun) on the benchmarks' lattice
// (tests/benchmarks/lattice.hpp) with the paper's frictional law, under mpirun: particle-steps per
// second in all and per rank, the halo traffic (bytes per particle-step and messages per step), the
// load imbalance (the most particles a rank owns over the mean) and the redistributions.
//
//   mpirun -np 2 throughput_mpi --dim 2 --particles 200000 --steps 200
//   mpirun -np 2 throughput_mpi --particles 200000 --gamma-n 0 --gamma-t 0   # the law of scripts/vs_lammps.sh
//   mpirun -np 2 throughput_mpi --packing spheres.dump --gamma-n 0 --gamma-t 0   # a packing file, as throughput's
//
// Every rank builds the whole lattice (or reads the whole file) and keeps its own part: the
// set-up's memory grows with the whole scene (fine for the sizes timed here), the steps' with a
// rank's part. The time step is throughput's: t_c / 50 of two particles of the mean radius (Eq. 22).
// Timed: the steps, between barriers, after the first forces.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <mpi.h>

#include <micromacro/io/packing_files.hpp>
#include <micromacro/micromacro.hpp>
#include <micromacro/mpi/distributed_run.hpp>

#include "../../examples/command_line.hpp"
#include "timed_particles.hpp"

namespace mm = micromacro;

namespace {
struct Options {
    int dim = 2;
    std::size_t particles = 20000, steps = 200;
    double k = 1e5, kt = 2e4, mu = 0.5, gamma_n = 0.1, gamma_t = 0.02;  // throughput's defaults, the paper's
    double density = 2000.0;
    std::string packing;                                                  // a file instead of the lattice
    mm::io::PackingFormat format = mm::io::PackingFormat::csv;
    bool json = false, no_energy = false, equal_slabs = false;
};

template <int dim>
int run(const Options& o) {
    // A file's box and periodic axes are the dump's (a CSV's: the particles' extent, no periodic axis).
    const auto [x, r, domain] = benchmark::timed_particles<dim>(o.packing, o.format, {}, "", o.particles);
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(o.k, o.gamma_n), mm::CundallStrack(o.kt, o.gamma_t, o.mu)};
    mm::BasicSimulation<dim, double, mm::FrictionalLinear> whole(law, domain);
    for (std::size_t i = 0; i < x.size(); ++i) whole.particles().add(x[i], r[i], mm::sphere_mass(o.density, r[i]));
    whole.set_time_step(benchmark::mean_contact_duration(r, o.density, o.k, o.gamma_n) / 50);
    whole.set_track_energy(!o.no_energy);
    using Run = mm::mpi::DistributedRun<decltype(whole)>;
    Run run(MPI_COMM_WORLD, whole, Run::Start::fresh, Run::Input::whole, o.equal_slabs ? Run::Split::equal : Run::Split::balanced);
    MPI_Barrier(MPI_COMM_WORLD);
    const auto start = std::chrono::steady_clock::now();
    run.run(o.steps);
    MPI_Barrier(MPI_COMM_WORLD);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    int ranks = 1, rank = 0;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    const unsigned long long mine[3] = {run.owned(), run.halo_bytes_per_step(), run.halo_messages_per_step()};
    unsigned long long most[3], sum[3];
    MPI_Reduce(mine, most, 3, MPI_UNSIGNED_LONG_LONG, MPI_MAX, 0, MPI_COMM_WORLD);
    MPI_Reduce(mine, sum, 3, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
    if (rank != 0) return 0;
    const double n = static_cast<double>(x.size()), pps = n * o.steps / seconds;
    const double imbalance = most[0] / (sum[0] / double(ranks)), halo = sum[1] / n;
    const auto& dims = run.comm().split().dims;
    std::string split = std::to_string(dims[0]);
    for (int a = 1; a < dim; ++a) split += "x" + std::to_string(dims[a]);
    split += o.equal_slabs ? ", equal slabs" : ", balanced";
    if (o.json)
        std::printf("{\"dim\": %d, \"particles\": %zu, \"steps\": %zu, \"ranks\": %d, \"split\": \"%s\", \"seconds\": %.6g, "
                    "\"particle_steps_per_second\": %.6g, \"per_rank\": %.6g, \"halo_bytes_per_particle_step\": %.4g, "
                    "\"halo_messages_per_step\": %llu, \"imbalance\": %.4f, \"redistributions\": %zu, \"dt\": %.6g, \"skin\": %.6g, \"energy_books\": %s}\n",
                    dim, x.size(), o.steps, ranks, split.c_str(), seconds, pps, pps / ranks, halo, most[2], imbalance, run.redistributions(),
                    whole.time_step(), run.skin(), o.no_energy ? "false" : "true");
    else
        std::printf("%dD frictional lattice: %zu particles on %d ranks (%s), %zu steps in %.3f s: %.3g particle-steps/s "
                    "(%.3g per rank); halo %.1f bytes per particle-step, at most %llu messages per step and rank; "
                    "imbalance %.3f; %zu redistributions; energy books %s\n",
                    dim, x.size(), ranks, split.c_str(), o.steps, seconds, pps, pps / ranks, halo, most[2], imbalance, run.redistributions(),
                    o.no_energy ? "off" : "on");
    return 0;
}
}  // namespace

int main(int argc, char** argv) {
    const micromacro::mpi::Runtime mpi(argc, argv);
    Options o;
    CLI::App app{"Particle-steps per second of the serial engine over MPI ranks (run under mpirun)"};
    auto* dim = app.add_option("--dim", o.dim, "2 or 3 (with --packing: the file's, a CSV 3 if it has a y column)")
                    ->check(CLI::IsMember({2, 3}))
                    ->capture_default_str();
    auto* particles = app.add_option("--particles", o.particles, "particles of the lattice")->capture_default_str();
    app.add_option("--packing", o.packing,
                   "time this packing instead: a LAMMPS dump (box and periodic axes from it) or a CSV as analyze_packing "
                   "reads it (x,z,r in 2D, x,y,z,r in 3D)")
        ->check(CLI::ExistingFile)
        ->excludes(particles);
    app.add_option("--density", o.density, "particle density (kg/m^3): masses, and t_c")->check(micromacro::cli::positive())->capture_default_str();
    app.add_option("--steps", o.steps, "time steps to time")->check(CLI::Range(std::size_t{1}, std::size_t{1} << 40))->capture_default_str();
    app.add_option("--k", o.k, "normal stiffness (N/m)")->capture_default_str();
    app.add_option("--gamma-n", o.gamma_n, "normal damping gamma_0 (kg/s)")->capture_default_str();
    app.add_option("--kt", o.kt, "tangential stiffness (N/m)")->capture_default_str();
    app.add_option("--gamma-t", o.gamma_t, "tangential damping (kg/s)")->capture_default_str();
    app.add_option("--mu", o.mu, "friction coefficient")->capture_default_str();
    app.add_flag("--equal-slabs", o.equal_slabs, "split the box into equal slabs (DistributedRun::Split::equal) instead of slabs of equal shares");
    app.add_flag("--json", o.json, "one JSON line instead of text");
    app.add_flag("--no-energy", o.no_energy, "without the energy books (on by default, as in the serial throughput)");
    // Every rank reads the same command line and refuses the same input: the first rank says so.
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    int status = 0;
    try {
        mm::cli::prepare_parse(app, argc, argv);
        app.parse(argc, argv);
        if (!o.packing.empty()) {
            o.format = mm::io::guess_format(o.packing);
            if (dim->count() == 0) o.dim = mm::io::guess_dimension(o.packing, o.format);
        }
        status = o.dim == 2 ? run<2>(o) : run<3>(o);
    } catch (const CLI::ParseError& e) {
        std::ostringstream silent;
        status = rank == 0 ? app.exit(e) : app.exit(e, silent, silent);
        if (status != 0) status = 1;
    } catch (const micromacro::InputError& e) {
        if (rank == 0) std::fprintf(stderr, "throughput_mpi: %s\n", e.what());
        status = 1;
    } catch (const std::exception& e) {  // may have stopped this rank alone: the others would wait for it
        std::fprintf(stderr, "throughput_mpi (rank %d): %s\n", rank, e.what());
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    return status;
}
