// The MPI layer's decomposition and halo, run under mpirun with 1-4 ranks (tests/CMakeLists.txt):
// the most slabs go along the longest axis; every particle of a periodic packing has exactly one
// owner; each rank receives as ghosts exactly the particles with an image within the halo width
// of its subdomain, once each, at their owners' positions (checked against every image of every
// particle, periodic ones included); the forces and torques on each rank's own particles,
// computed by the serial engine in the whole box from its own and ghost particles alone, are the
// serial run's to round-off; and a refresh brings every ghost its owner's new state. In 2D and
// 3D, with the frictional law (new contacts start their springs from the time they have touched,
// so the tangential forces are not zero).
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include <micromacro/mpi/halo.hpp>

#include "support/mpi_runtime.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(mpi_halo)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
using mmtest::Dims;

namespace {
// The same packing on every rank: n particles, radii 0.5-1.5 mm, placed at random with overlaps at
// volume fraction 0.6 in a periodic cube, moving and turning at random.
template <int dim>
auto packing(std::size_t n) {
    const double L = std::pow(n * mmtest::mean_particle_volume<dim>(0.5e-3, 1.5e-3) / 0.6, 1.0 / dim);
    const auto p = mmtest::random_packing<dim>(n, 0.5e-3, 1.5e-3, L, 7, true, true);
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(mmtest::k, mmtest::gamma0), mm::CundallStrack(0.2 * mmtest::k, 0.02, 0.5)};
    mm::BasicSimulation<dim, double, mm::FrictionalLinear> sim(law, mmtest::periodic_box<dim>(L));
    std::mt19937_64 rng(11);
    std::normal_distribution<double> N(0.0, 0.1);
    for (std::size_t i = 0; i < p.x.size(); ++i) {
        sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(mmtest::rho, p.r[i]));
        for (int a = 0; a < dim; ++a) sim.particles().velocity()[i][a] = N(rng);
        auto& w = sim.particles().template get<mm::field::AngularVelocity>()[i];
        if constexpr (dim == 2) w = 100.0 * N(rng);
        else w = mm::Vec<3>(100.0 * N(rng), 100.0 * N(rng), 100.0 * N(rng));
    }
    sim.set_time_step(mm::contact_duration(mmtest::k, mmtest::gamma0, mm::sphere_mass(mmtest::rho, 0.5e-3) / 2) / 50);
    sim.set_skin(0.2e-3);
    return sim;
}

template <class Sim>
mm::mpi::ParticleRecord record(const Sim& sim, std::size_t i) {
    return mm::mpi::record_of(sim.particles(), i, sim.particles().id(i));
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(owners_ghosts_and_forces_match_the_serial_run, D, Dims) {
    constexpr int dim = D::value;
    auto serial = packing<dim>(dim == 2 ? 300 : 400);
    serial.prepare();  // the serial forces
    const std::size_t n = serial.particles().size();
    const mm::mpi::CartesianComm<dim> comm(MPI_COMM_WORLD, serial.domain());
    const auto& split = comm.split();
    const double width = 2 * 1.5e-3 + serial.skin();  // the largest contact distance plus the skin

    // Owners: each particle exactly once over the ranks.
    std::vector<mm::mpi::ParticleRecord> owned;
    for (std::size_t i = 0; i < n; ++i)
        if (split.owns(serial.particles().position()[i])) owned.push_back(record(serial, i));
    std::vector<int> mine(n, 0), owners(n, 0);
    for (const auto& p : owned) mine[p.id] = 1;
    MPI_Allreduce(mine.data(), owners.data(), static_cast<int>(n), MPI_INT, MPI_SUM, comm.comm());
    BOOST_TEST(std::all_of(owners.begin(), owners.end(), [](int k) { return k == 1; }));

    // Ghosts: exactly the other ranks' particles with an image within the halo width of the
    // subdomain, each once, at the owner's position.
    const mm::mpi::Halo<dim> halo(comm, owned, width);
    const auto& ghosts = halo.ghosts();
    std::map<mm::Index, int> got, expected;
    const auto by_id = serial.particles().index_by_id();
    bool at_owners_position = true;
    for (const auto& g : ghosts) {
        ++got[g.id];
        at_owners_position &= g.x == mm::mpi::record_vector<dim>(serial.particles().position()[by_id[g.id]]);
    }
    BOOST_TEST(at_owners_position);
    for (std::size_t i = 0; i < n; ++i) {
        if (split.owns(serial.particles().position()[i])) continue;
        const auto x = mm::mpi::record_vector<dim>(serial.particles().position()[i]);
        bool near = false;
        for (int sx = -1; sx <= 1; ++sx)
            for (int sy = -1; sy <= 1; ++sy)
                for (int sz = (dim == 3 ? -1 : 0); sz <= (dim == 3 ? 1 : 0); ++sz) {
                    const std::array<int, 3> s{sx, sy, sz};
                    bool inside_grown = true;
                    for (int a = 0; a < dim; ++a) {
                        const double L = split.hi[a] - split.lo[a];
                        const double y = s[a] == 0 ? x[a] : s[a] > 0 ? x[a] + L : x[a] - L;
                        // An axis of one slab: no images (the rank's engine wraps it itself).
                        if (split.dims[a] == 1) inside_grown &= s[a] == 0;
                        else inside_grown &= y >= split.sub_lo(a) - width && y < split.sub_hi(a) + width;
                    }
                    near |= inside_grown;
                }
        if (near) expected[serial.particles().id(i)] = 1;
    }
    BOOST_TEST(got.size() == expected.size());
    BOOST_TEST((got == expected), "ghosts differ from the expected ones on rank " << comm.rank());

    // Forces: the serial engine in the whole box on this rank's own and ghost particles, binned
    // in the rank's window (CartesianSplit::search_window), gives its own particles the serial
    // forces and torques.
    mm::BasicSimulation<dim, double, mm::FrictionalLinear> local(serial.law(), serial.domain());
    local.set_search_window(split.search_window(width, serial.skin()));
    std::vector<mm::Index> global;
    for (const auto* set : std::array<const std::vector<mm::mpi::ParticleRecord>*, 2>{&owned, &ghosts})
        for (const auto& p : *set) {
            mm::Vec<dim> x, v;
            for (int a = 0; a < dim; ++a) x[a] = p.x[a], v[a] = p.v[a];
            const std::size_t i = local.particles().add(x, p.radius, p.mass, p.inertia);
            local.particles().velocity()[i] = v;
            auto& w = local.particles().template get<mm::field::AngularVelocity>()[i];
            if constexpr (dim == 2) w = p.w[2];
            else w = mm::Vec<3>(p.w[0], p.w[1], p.w[2]);
            global.push_back(p.id);
        }
    local.set_time_step(serial.time_step());
    local.set_skin(serial.skin());
    local.prepare();
    // The largest serial force and torque, for relative tolerances: torques come from the
    // tangential forces alone, which are far smaller than the normal ones here, so they are
    // compared on their own scale.
    double scale = 0.0, torque_scale = 0.0;
    for (const auto& f : serial.particles().force()) scale = std::max(scale, f.norm());
    const auto& torque = serial.particles().template get<mm::field::Torque>();
    const auto& local_torque = local.particles().template get<mm::field::Torque>();
    for (const auto& t : torque) torque_scale = std::max(torque_scale, std::abs(mm::DimTraits<dim>::squared_norm(t)));
    torque_scale = std::sqrt(torque_scale);
    BOOST_TEST_REQUIRE(torque_scale > 0.0);
    double worst = 0.0, worst_torque = 0.0;
    for (std::size_t i = 0; i < local.particles().size(); ++i) {
        const std::size_t k = local.particles().id(i);  // the order added
        if (k >= owned.size()) continue;                  // a ghost: its force is not all there
        const std::size_t s = by_id[global[k]];
        worst = std::max(worst, (local.particles().force()[i] - serial.particles().force()[s]).norm() / scale);
        const auto dt = local_torque[i] - torque[s];
        worst_torque = std::max(worst_torque, std::sqrt(mm::DimTraits<dim>::squared_norm(dt)) / torque_scale);
    }
    BOOST_TEST(worst < 1e-11, "rank " << comm.rank() << ": largest force difference " << worst << " of the largest force");
    BOOST_TEST(worst_torque < 1e-11, "rank " << comm.rank() << ": largest torque difference " << worst_torque);
}

// A refresh sends the owners' new positions, velocities and angular velocities along the swaps of
// the halo's building: every ghost then equals the same image in a halo built afresh from the
// moved particles (moved by far less than the distance at which the halo's membership changes).
BOOST_AUTO_TEST_CASE_TEMPLATE(a_refresh_brings_the_ghosts_their_owners_new_state, D, Dims) {
    constexpr int dim = D::value;
    auto serial = packing<dim>(dim == 2 ? 300 : 400);
    const mm::mpi::CartesianComm<dim> comm(MPI_COMM_WORLD, serial.domain());
    const double width = 2 * 1.5e-3 + serial.skin();
    std::vector<mm::mpi::ParticleRecord> owned;
    for (std::size_t i = 0; i < serial.particles().size(); ++i)
        if (comm.split().owns(serial.particles().position()[i])) owned.push_back(record(serial, i));
    mm::mpi::Halo<dim> halo(comm, owned, width);
    std::mt19937_64 rng(17 + comm.rank());
    std::normal_distribution<double> N(0.0, 1.0);
    for (auto& p : owned)
        for (int a = 0; a < 3; ++a) {
            if (a < dim) p.x[a] += 1e-9 * N(rng);  // 1 nm: the owners stay, the halo's members too (almost surely)
            if (a < dim) p.v[a] = N(rng);          // a 2D record's z components stay 0, its spin is about z
            if (dim == 3 || a == 2) p.w[a] = N(rng);
        }
    halo.refresh(comm, owned);
    const mm::mpi::Halo<dim> fresh(comm, owned, width);
    BOOST_TEST_REQUIRE(fresh.ghosts().size() == halo.ghosts().size());
    bool same = true;
    for (std::size_t k = 0; k < fresh.ghosts().size(); ++k) {
        const auto &a = halo.ghosts()[k], &b = fresh.ghosts()[k];
        same &= a.id == b.id && a.x == b.x && a.v == b.v && a.w == b.w && a.radius == b.radius;
    }
    BOOST_TEST(same, "rank " << comm.rank() << ": a refreshed ghost differs from the fresh halo's");
    // The refresh moved the ghosts: they are not the state they were built with.
    const mm::mpi::Halo<dim> before(comm, [&] {
        std::vector<mm::mpi::ParticleRecord> o;
        for (std::size_t i = 0; i < serial.particles().size(); ++i)
            if (comm.split().owns(serial.particles().position()[i])) o.push_back(record(serial, i));
        return o;
    }(), width);
    std::size_t moved = 0;
    for (std::size_t k = 0; k < before.ghosts().size() && k < halo.ghosts().size(); ++k) moved += before.ghosts()[k].v != halo.ghosts()[k].v;
    BOOST_TEST(moved == halo.ghosts().size());
}

// The split puts the most slabs along the longest axis, of equal ones the last (the axis the
// engine's spatial order runs slowest along): MPI_Dims_create's counts, largest first, onto the
// axes longest first; dims given by the caller stay as given.
BOOST_AUTO_TEST_CASE(the_most_slabs_go_along_the_longest_axis) {
    const int ranks = mmtest::world_size();
    std::array<int, 3> balanced{};
    MPI_Dims_create(ranks, 3, balanced.data());  // largest first
    auto dims_over = [](const mm::Domain<3>& box) {
        const mm::mpi::CartesianComm<3> comm(MPI_COMM_WORLD, box);
        return comm.split().dims;
    };
    const mm::Vec<3> zero = mm::Vec<3>::Zero();
    const auto cube = dims_over(mm::Domain<3>::fully_periodic(zero, mm::Vec<3>::Constant(0.01)));
    BOOST_TEST((cube == std::array<int, 3>{balanced[2], balanced[1], balanced[0]}));
    const auto long_x = dims_over(mm::Domain<3>::fully_periodic(zero, mm::Vec<3>(0.04, 0.01, 0.02)));
    BOOST_TEST((long_x == std::array<int, 3>{balanced[0], balanced[2], balanced[1]}));
    const mm::mpi::CartesianComm<3> fixed(MPI_COMM_WORLD, mm::Domain<3>::fully_periodic(zero, mm::Vec<3>::Constant(0.01)), {ranks, 1, 1});
    BOOST_TEST((fixed.split().dims == std::array<int, 3>{ranks, 1, 1}));
}

BOOST_AUTO_TEST_SUITE_END()
