// The serial engine run over MPI ranks (mpi::DistributedRun) under mpirun with 1-4 ranks: 200
// steps of a dense frictional periodic packing, each rank stepping its own particles with the
// ghosts of its halo refreshed after every particle pass, give every particle the serial run's
// position, velocity, angular velocity, force and torque: the same bits on one thread per rank
// (built without fused multiply-adds; each rank sums a particle's forces in the serial order),
// to round-off with threads, with the particles staying on their ranks and with them handed to
// new ranks every few steps. In 2D and 3D. Contacts press, turn and slide: the tangential springs
// carry the history the comparison checks. One rank gives the serial run's bits. The same in a
// box of walls, one moved by Eq. 17 and one by Eq. 18, whose forces are summed over the ranks
// in the serial order (the serial bits; in rank order, round-off). Where no particle has more
// than two contacts (the order of a sum of two does not matter) any number of ranks gives the
// serial bits with threads too, pairs across the periodic boundary between ranks and wraps included.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>

#include <micromacro/mpi/distributed_run.hpp>
#include <micromacro/mpi/energy.hpp>

#include "support/expect_error.hpp"
#include "support/mpi_lattice.hpp"
#include "support/mpi_runtime.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(mpi_distributed_run)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
using mmtest::Dims;

namespace {
using mmtest::lattice;

template <int dim>
double largest(const std::vector<mm::Vec<dim>>& v) {
    double m = 0.0;
    for (const auto& x : v) m = std::max(m, x.norm());
    return m;
}
template <int dim, class A>
double norm(const A& w) {
    return std::sqrt(mm::DimTraits<dim>::squared_norm(w));
}
}  // namespace

// With a skin of 0.5 mm the particles stay with their first ranks for the 200 steps; with 10 um
// they are handed to new ranks every few steps (the springs with them), and some change ranks.
// This rank's share of `serial`'s particles for DistributedRun's Input::share: a contiguous run of
// the serial numbering (rank 0's first), wherever its particles are.
template <class Sim>
Sim share_of(const Sim& serial) {
    const int rank = mmtest::world_rank(), ranks = mmtest::world_size();
    Sim share = [&] {
        if constexpr (Sim::has_walls)
            return Sim(serial.law(), serial.domain(), serial.walls(), {}, {}, serial.template body_force<mm::AffineDamping>(),
                       serial.template body_force<mm::Gravity<Sim::dimension>>());
        else return Sim(serial.law(), serial.domain());
    }();
    const auto& s = serial.particles();
    const std::size_t begin = s.size() * rank / ranks, end = s.size() * (rank + 1) / ranks;
    for (std::size_t i = begin; i < end; ++i) {
        const std::size_t k = share.particles().add(s.position()[i], s.radius()[i], s.mass()[i], s.template get<mm::field::Inertia>()[i]);
        share.particles().velocity()[k] = s.velocity()[i];
        share.particles().template get<mm::field::AngularVelocity>()[k] = s.template get<mm::field::AngularVelocity>()[i];
    }
    share.set_time_step(serial.time_step());
    share.set_skin(serial.skin());
    return share;
}

// Returns the split's box at the start and at the end (rank-independent). `shares`: each rank
// passes its share of the particles (share_of) instead of the whole scene. `change`: after 100
// steps, the friction coefficient drops from 0.5 to 0.2 and a damping doubles, in every run.
// `serial_wall_sums`: as DistributedRun::set_serial_wall_sums. `sorts`, if given: how often the
// serial engine sorted its particles during the run. `split`: DistributedRun::Split (equal slabs,
// whose boundaries the scenes' rows sit on, unless said).
template <class Sim>
std::pair<mm::mpi::CartesianSplit<Sim::dimension>, mm::mpi::CartesianSplit<Sim::dimension>> compare_with_serial(
    Sim serial, bool redistributes, bool migrates, bool shares = false, int threads = 1, double round_off = 2e-11,
    bool change = false, bool serial_wall_sums = true, std::size_t* sorts = nullptr,
    typename mm::mpi::DistributedRun<Sim>::Split split = mm::mpi::DistributedRun<Sim>::Split::equal) {
    constexpr int dim = Sim::dimension;
    const double skin = serial.skin();
    serial.set_track_energy(true);  // the distributed run books as the scene does
    using Run = mm::mpi::DistributedRun<Sim>;
    const std::optional<Sim> share = shares ? std::optional<Sim>(share_of(serial)) : std::nullopt;
    mm::mpi::DistributedRun distributed(MPI_COMM_WORLD, shares ? *share : serial, Run::Start::fresh,
                                        shares ? Run::Input::share : Run::Input::whole, split);  // from the state before the steps
    distributed.set_threads(threads);
    distributed.set_serial_wall_sums(serial_wall_sums);
    serial.set_threads(threads);  // one rank: the same thread shares, the same bits
    const auto first_split = distributed.comm().split();
    // The round-off level: the serial run with its particles numbered backwards (the same sums
    // in another order).
    auto backwards = serial;
    std::vector<mm::Index> order(serial.particles().size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<mm::Index>(order.size() - 1 - i);
    backwards.renumber(order);
    const std::size_t sorts_before = serial.spatial_sorts();
    serial.prepare();
    backwards.prepare();
    const auto& s = serial.particles();
    const auto& p = distributed.local().particles();
    const int rank = distributed.comm().rank();
    std::size_t sliding = 0, contacts = 0, wall_contacts = 0;  // at the three comparisons
    // Every owned particle against the serial one, relative to the serial run's largest value
    // (positions: to a radius), after `steps` steps.
    auto compare = [&](int steps) {
        const auto& w = s.template get<mm::field::AngularVelocity>();
        const auto& t = s.template get<mm::field::Torque>();
        const auto& local_w = p.template get<mm::field::AngularVelocity>();
        const auto& local_t = p.template get<mm::field::Torque>();
        double w_scale = 0.0, t_scale = 0.0;
        for (std::size_t i = 0; i < s.size(); ++i) w_scale = std::max(w_scale, norm<dim>(w[i])), t_scale = std::max(t_scale, norm<dim>(t[i]));
        const double x_scale = 1e-3, v_scale = largest<dim>(s.velocity()), f_scale = largest<dim>(s.force());
        BOOST_TEST_REQUIRE((v_scale > 0 && f_scale > 0 && w_scale > 0 && t_scale > 0));
        // The serial engine sorts scenes from auto_sort_min_particles on; the ranks follow its
        // numbering, and each particle's place in it is its serial index.
        BOOST_TEST(distributed.spatial_sorts() == serial.spatial_sorts(), "step " << steps);
        const auto by_id = s.index_by_id();
        double dx = 0, dv = 0, dw = 0, df = 0, dt = 0;
        for (std::size_t i = 0; i < distributed.owned(); ++i) {
            const std::size_t k = by_id[distributed.global_id(i)];
            BOOST_TEST_REQUIRE(distributed.place(i) == k, "step " << steps << ": particle " << distributed.global_id(i) << "'s place");
            dx = std::max(dx, serial.domain().separation(p.position()[i], s.position()[k]).norm() / x_scale);
            dv = std::max(dv, (p.velocity()[i] - s.velocity()[k]).norm() / v_scale);
            df = std::max(df, (p.force()[i] - s.force()[k]).norm() / f_scale);
            dw = std::max(dw, norm<dim>(decltype(local_w[i])(local_w[i] - w[k])) / w_scale);
            dt = std::max(dt, norm<dim>(decltype(local_t[i])(local_t[i] - t[k])) / t_scale);
        }
        double bv = 0, bf = 0;  // the serial run numbered backwards against the serial run
        const auto back = backwards.particles().index_by_id();
        for (std::size_t i = 0; i < s.size(); ++i) {
            bv = std::max(bv, (backwards.particles().velocity()[back[s.id(i)]] - s.velocity()[i]).norm() / v_scale);
            bf = std::max(bf, (backwards.particles().force()[back[s.id(i)]] - s.force()[i]).norm() / f_scale);
        }
        BOOST_TEST_MESSAGE(dim << "D, skin " << skin << ", rank " << rank << ", after " << steps << " steps, relative differences: position " << dx
                               << ", velocity " << dv << ", angular velocity " << dw << ", force " << df << ", torque " << dt
                               << "; the serial run numbered backwards: velocity " << bv << ", force " << bf);
        // Round-off: the serial run numbered backwards differs by up to 4.2e-12 after 200 steps,
        // runs on 2-4 ranks in a box of walls whose forces are summed in rank order by up to
        // 3e-13, with threads within ranks (other sums) by up to 1.7e-11 (the messages above,
        // --log_level=message). A rank that missed a contact or a spring would be off by the
        // contact's share of the force, many orders more. One rank runs the serial engine on the
        // serial box: the same bits.
        // (With threads the shares of the pair list follow its length, which the rebuilds set.)
        if (mmtest::world_size() == 1 && threads == 1)
            BOOST_TEST((dx == 0 && dv == 0 && dw == 0 && df == 0 && dt == 0), "one rank, step " << steps);
        // On one thread each rank sums a particle's forces in the serial order (its pairs in the
        // order of the serial numbering), and the walls' forces are summed in the serial order
        // too, so any number of ranks gives the serial bits. With fused multiply-adds a rank's
        // pair loop (which books half of a pair with a ghost) may fuse other products than the
        // serial one: the same bits were measured there too, but only round-off is promised.
#ifndef MICROMACRO_FP_CONTRACT
        const bool serial_bits = threads == 1 && (serial_wall_sums || !Sim::has_walls);
        if (serial_bits)
            BOOST_TEST((dx == 0 && dv == 0 && dw == 0 && df == 0 && dt == 0), "rank " << rank << ", step " << steps << ": the serial bits");
#endif
        BOOST_TEST(dx < round_off, "rank " << rank << ", step " << steps << ": positions differ by " << dx << " of a radius");
        BOOST_TEST(dv < round_off, "rank " << rank << ", step " << steps << ": velocities by " << dv);
        BOOST_TEST(dw < round_off, "rank " << rank << ", step " << steps << ": angular velocities by " << dw);
        BOOST_TEST(df < round_off, "rank " << rank << ", step " << steps << ": forces by " << df);
        BOOST_TEST(dt < round_off, "rank " << rank << ", step " << steps << ": torques by " << dt);
        if constexpr (Sim::has_walls) {  // every rank holds every wall
            const auto& ws = serial.walls();
            const auto& wd = distributed.local().walls();
            double w_force = 0.0, dh = 0.0, du = 0.0, dfw = 0.0;
            for (std::size_t k = 0; k < ws.size(); ++k) w_force = std::max(w_force, ws[k].force.norm());
            for (std::size_t k = 0; k < ws.size(); ++k) {
                dh = std::max(dh, std::abs(wd[k].offset - ws[k].offset) / x_scale);
                du = std::max(du, std::abs(wd[k].speed - ws[k].speed) / v_scale);
                dfw = std::max(dfw, (wd[k].force - ws[k].force).norm() / w_force);
            }
            BOOST_TEST_MESSAGE("walls: offset " << dh << ", speed " << du << ", force " << dfw);
            if (mmtest::world_size() == 1 && threads == 1) BOOST_TEST((dh == 0 && du == 0 && dfw == 0), "one rank, walls, step " << steps);
#ifndef MICROMACRO_FP_CONTRACT
            if (serial_bits) BOOST_TEST((dh == 0 && du == 0 && dfw == 0), "rank " << rank << ", walls, step " << steps << ": the serial bits");
#endif
            BOOST_TEST(dh < round_off, "rank " << rank << ", step " << steps << ": wall offsets differ by " << dh << " of a radius");
            BOOST_TEST(du < round_off, "rank " << rank << ", step " << steps << ": wall speeds by " << du);
            BOOST_TEST(dfw < round_off, "rank " << rank << ", step " << steps << ": wall forces by " << dfw);
        }
        // The energies of the whole scene, each part against the serial one relative to the
        // total (kinetic energy is a small part of it in a packing this still).
        const mm::EnergyState e = mm::mpi::energy(distributed), es = serial.energy();
        const double parts[][2] = {{e.kinetic_translational, es.kinetic_translational}, {e.kinetic_rotational, es.kinetic_rotational},
                                   {e.kinetic_walls, es.kinetic_walls},                 {e.elastic_normal, es.elastic_normal},
                                   {e.elastic_tangential, es.elastic_tangential},       {e.gravitational, es.gravitational}};
        double de = 0.0;
        for (const auto& part : parts) de = std::max(de, std::abs(part[0] - part[1]) / es.total());
        BOOST_TEST_MESSAGE("energies: " << de << " of the total " << es.total() << " J (elastic tangential " << es.elastic_tangential
                                        << ", kinetic " << es.kinetic() << ")");
        BOOST_TEST_REQUIRE(es.total() > 0.0);
        if (mmtest::world_size() == 1 && threads == 1) BOOST_TEST(de == 0.0, "one rank, energies, step " << steps);
        BOOST_TEST(de < round_off, "rank " << rank << ", step " << steps << ": energies by " << de << " of the total");
        // The books, entry by entry, relative to the largest of the total energy, the energy
        // dissipated and the work put in; and the energy they opened with. A pair with a ghost
        // booked whole on both its ranks, or the pressure's work booked on every rank, would be
        // off by that pair's or that wall's share, orders above round-off.
        const mm::OpenBooks b = mm::mpi::open_books(distributed);
        const mm::EnergyBooks& bs = serial.books();
        const double b_scale = std::max({es.total(), bs.dissipated(), std::abs(bs.work_in())});
        const double entries[][2] = {{b.books.dissipated_normal, bs.dissipated_normal},
                                     {b.books.dissipated_tangential, bs.dissipated_tangential},
                                     {b.books.dissipated_sliding, bs.dissipated_sliding},
                                     {b.books.dissipated_background, bs.dissipated_background},
                                     {b.books.dissipated_walls, bs.dissipated_walls},
                                     {b.books.work_by_walls, bs.work_by_walls},
                                     {b.books.work_by_deformation, bs.work_by_deformation},
                                     {b.initial_energy, serial.initial_energy()}};
        double db = 0.0;
        for (const auto& entry : entries) db = std::max(db, std::abs(entry[0] - entry[1]) / b_scale);
        const double residual = mm::mpi::energy_residual(distributed);
        BOOST_TEST_MESSAGE("books: " << db << " of " << b_scale << " J (dissipated " << bs.dissipated() << ", work in " << bs.work_in()
                                     << "); residual " << residual << " against the serial " << serial.energy_residual());
        if (mmtest::world_size() == 1 && threads == 1) BOOST_TEST(db == 0.0, "one rank, books, step " << steps);
        BOOST_TEST(db < round_off, "rank " << rank << ", step " << steps << ": books by " << db);
        BOOST_TEST(std::abs(residual - serial.energy_residual()) < round_off, "rank " << rank << ", step " << steps << ": residual " << residual);
        serial.for_each_contact([&](const auto& c) {
            ++contacts;
            sliding += c.sliding;
            wall_contacts += c.wall;
        });
    };
    compare(0);
    std::vector<mm::Index> first_owned;
    for (std::size_t i = 0; i < distributed.owned(); ++i) first_owned.push_back(distributed.global_id(i));
    std::sort(first_owned.begin(), first_owned.end());
    for (int steps : {100, 200}) {
        if (change && steps == 200) {
            auto law = serial.law();
            law.tangential = mm::CundallStrack(law.tangential.stiffness(), law.tangential.damping(), 0.2);
            serial.law() = law, backwards.law() = law;
            distributed.set_law(law);
            if constexpr (Sim::has_walls) {
                auto damping = serial.template body_force<mm::AffineDamping>();
                damping.translational *= 2.0, damping.rotational *= 2.0;
                serial.template body_force<mm::AffineDamping>() = damping, backwards.template body_force<mm::AffineDamping>() = damping;
                distributed.set_body_force(damping);
            }
        }
        serial.run(100);
        backwards.run(100);
        distributed.run(100);
        compare(steps);
    }
    // Every particle is some rank's.
    unsigned long long mine = distributed.owned(), all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    BOOST_TEST(all == s.size());
    // The books saw every kind of contact dissipation, and the walls' work where there are walls.
    BOOST_TEST(serial.books().dissipated_normal > 0.0);
    BOOST_TEST(serial.books().dissipated_tangential > 0.0);
    BOOST_TEST(serial.books().dissipated_sliding > 0.0);
    if constexpr (Sim::has_walls) {  // and gravity, whose potential energy a rank counting its ghosts' would change
        BOOST_TEST((serial.books().work_by_walls != 0.0 && serial.books().dissipated_background > 0.0));
        BOOST_TEST(std::abs(serial.energy().gravitational) > 1e-2 * serial.energy().total());
    }
    // The springs were loaded and some contacts slid: the comparison saw tangential history.
    BOOST_TEST(contacts > 3 * s.size());
    BOOST_TEST(sliding > 0u);
    if constexpr (Sim::has_walls) {  // the walls were pressed, and the two moving ones moved
        BOOST_TEST(wall_contacts >= 3u * 2 * dim * (dim == 2 ? 19 : 49), "every outer particle on its wall");
        BOOST_TEST(std::abs(serial.walls()[2 * dim - 1].offset - serial.walls()[2 * dim - 1].initial_offset) > 19e-6);
        BOOST_TEST(std::abs(serial.walls()[1].offset - serial.walls()[1].initial_offset) > 1e-7);
    }
    BOOST_TEST((distributed.redistributions() > 5) == redistributes, distributed.redistributions() << " redistributions");
    unsigned long long arrived = 0, moved = 0;  // particles this rank owns now and did not at the start
    for (std::size_t i = 0; i < distributed.owned(); ++i) arrived += !std::binary_search(first_owned.begin(), first_owned.end(), distributed.global_id(i));
    MPI_Allreduce(&arrived, &moved, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    BOOST_TEST_MESSAGE(dim << "D, skin " << skin << ": " << distributed.redistributions() << " redistributions, " << moved << " particles changed ranks");
    if (migrates && mmtest::world_size() > 1) BOOST_TEST(moved > 0u, "no particle changed ranks: the test would not see a migration");
    if (sorts) *sorts = serial.spatial_sorts() - sorts_before;
    return {first_split, distributed.comm().split()};
}

constexpr int per_side(int dim) { return dim == 2 ? 18 : 8; }

BOOST_AUTO_TEST_CASE_TEMPLATE(two_hundred_steps_give_the_serial_state, D, Dims) {
    compare_with_serial(lattice<D::value>(per_side(D::value), 0.5e-3), false, false);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(particles_handed_to_new_ranks_keep_the_serial_state, D, Dims) {
    compare_with_serial(lattice<D::value>(per_side(D::value), 10e-6), true, true);
}

// The bounded box has rows on the boundaries between its 2 and 3 slabs (an odd number of rows per
// side) and rows half outside it; the unbounded one is split over the particles' extent, which
// the split follows at every redistribution: in by the 20 um the strain-controlled wall moved.
BOOST_AUTO_TEST_CASE_TEMPLATE(walls_moved_by_the_summed_forces_keep_the_serial_state, D, Dims) {
    constexpr int dim = D::value;
    const int rows = dim == 2 ? 19 : 7;
    compare_with_serial(mmtest::walled_lattice<dim>(rows, 10e-6, true), true, true);
    // The walls' forces summed in rank order instead: round-off.
    compare_with_serial(mmtest::walled_lattice<dim>(rows, 10e-6, true), true, true, false, 1, 2e-11, false, false);
    const auto still = compare_with_serial(mmtest::walled_lattice<dim>(rows, 0.5e-3, false), false, false);
    BOOST_TEST(still.second.hi[dim - 1] == still.first.hi[dim - 1], "no redistribution, the split stays");
    const auto [first, last] = compare_with_serial(mmtest::walled_lattice<dim>(rows, 10e-6, false), true, false);
    // The extent is the outer particles' (x + r), which also move by their own few micrometres.
    const double upper = last.hi[dim - 1] - first.hi[dim - 1], lower = last.lo[dim - 1] - first.lo[dim - 1];
    BOOST_TEST_MESSAGE(dim << "D: the split's ends along the loaded axis moved by " << lower << " and " << upper << " m");
    BOOST_TEST(upper < -12e-6);
    BOOST_TEST(upper > -30e-6);
    BOOST_TEST(std::abs(lower) < 8e-6, "the lower wall stays");
}

// A stress-controlled wall that takes its area from the period of a periodic axis cannot see it
// on a rank whose engine holds a slab of that axis: refused on every rank when the axis is split
// (2-4 ranks split the first axis), run on one.
BOOST_AUTO_TEST_CASE(a_wall_area_along_a_split_periodic_axis_is_refused) {
    const double L = 25e-3, H = 10e-3;
    mm::Walls<2> walls;
    walls.add_axis_aligned(1, true, 0.0);
    walls.add_axis_aligned(1, false, H, mm::StressControlled{100.0, 1e-3, 0.0});
    mm::BasicSimulation<2, double, mm::FrictionalLinear, mm::Walls<2>> sim(mmtest::lattice_law,
                                                                         mm::Domain<2>({0.0, 0.0}, {L, H}, {true, false}), walls);
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 4; ++j) sim.particles().add({(i + 0.5) * 2.5e-3, (j + 0.5) * 2.5e-3}, 1e-3, mm::sphere_mass(mmtest::rho, 1e-3));
    sim.set_time_step(1e-6);
    auto start = [&] { mm::mpi::DistributedRun run(MPI_COMM_WORLD, sim); };
    if (mmtest::world_size() == 1) start();
    else mmtest::expect_error(start, {"stress-controlled wall 1", "periodic axis 0", "give StressControlled::area"});
}

// Each rank passes only its share of the particles (a contiguous run of the serial numbering,
// across the whole box): they reach their owners, and the run is the serial one, in the periodic
// box and in the box of walls, whose split is the extent of every share's particles.
// A law and a damping changed between steps, as the biaxial test changes them between its
// preparation and its loading: the serial state still, with the particles handed on.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_law_changed_between_steps_keeps_the_serial_state, D, Dims) {
    compare_with_serial(lattice<D::value>(per_side(D::value), 10e-6), true, true, false, 1, 2e-11, true);
    compare_with_serial(mmtest::walled_lattice<D::value>(D::value == 2 ? 19 : 7, 0.5e-3, false), false, false, false, 1, 2e-11, true);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(shares_of_the_particles_give_the_serial_state, D, Dims) {
    compare_with_serial(lattice<D::value>(per_side(D::value), 10e-6), true, true, true);
    compare_with_serial(mmtest::walled_lattice<D::value>(D::value == 2 ? 19 : 7, 0.5e-3, false), false, false, true);
}

// From auto_sort_min_particles particles on, the serial engine sorts its particles spatially on
// its own, at its first neighbour search and at a search that finds the order decayed (the
// candidates' mean index gap doubled since its last sort). The ranks follow: every particle's
// place in the serial numbering stays its serial index through the sorts, and the run keeps the
// serial state (the serial bits without fused multiply-adds).
BOOST_AUTO_TEST_CASE_TEMPLATE(the_serial_engines_sorts_keep_the_serial_state, D, Dims) {
    constexpr int dim = D::value;
    std::size_t sorts = 0;
    compare_with_serial(mmtest::sorting_lattice<dim>(), true, true, false, 1, 2e-11, false, true, &sorts);
    BOOST_TEST(sorts == 1u, "sorted at the first search only: " << sorts);
    compare_with_serial(mmtest::sorting_lattice<dim>(std::pair{0, 200}), true, true, false, 1, 2e-11, false, true, &sorts);
    BOOST_TEST(sorts == 1u, "sorted within the run: " << sorts);
}

// The box a third longer along its last axis than the lattice, which fills the rest: equal slabs
// along that axis (the longest, which the ranks split first) would hold unequal shares (on two
// ranks the first slab holds 2/3 of the particles, the busiest rank 4/3 of the mean). The balanced split
// puts its boundaries where each slab holds an equal share, to a row of particles, and the run
// keeps the serial state whatever the split.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_balanced_split_gives_the_ranks_equal_shares, D, Dims) {
    constexpr int dim = D::value;
    const int per_side = dim == 2 ? 24 : 12;
    const double spacing = 1.99e-3, L = per_side * spacing;
    mm::Vec<dim> hi = mm::Vec<dim>::Constant(L);
    hi[dim - 1] = 4.0 / 3.0 * L;
    std::array<bool, dim> periodic;
    periodic.fill(true);
    mm::BasicSimulation<dim, double, mm::FrictionalLinear> scene(mmtest::lattice_law, mm::Domain<dim>(mm::Vec<dim>::Zero(), hi, periodic));
    mmtest::fill_lattice<dim>(scene, per_side, 10e-6, 0.0, spacing);
    using Run = mm::mpi::DistributedRun<decltype(scene)>;
    auto shares = [&](Run::Split split) {  // the busiest rank's particles over the mean
        Run run(MPI_COMM_WORLD, scene, Run::Start::fresh, Run::Input::whole, split);
        run.run(50);
        const unsigned long long mine = run.owned();
        unsigned long long most = 0, all = 0;
        MPI_Allreduce(&mine, &most, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
        MPI_Allreduce(&mine, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
        return double(most) / (double(all) / mmtest::world_size());
    };
    const double equal = shares(Run::Split::equal), balanced = shares(Run::Split::balanced);
    const auto dims = mm::mpi::CartesianComm<dim>(MPI_COMM_WORLD, scene.domain()).split().dims;
    const double row = double(dims[dim - 1]) / per_side;  // a row of particles in a slab's share
    BOOST_TEST_MESSAGE(dim << "D, " << mmtest::world_size() << " ranks: the busiest rank holds " << equal << " of the mean with equal slabs, "
                           << balanced << " balanced");
    if (dims[dim - 1] > 1) BOOST_TEST(equal > 1.2);  // 4/3 but for the rows on the boundaries
    BOOST_TEST(balanced <= 1.0 + row + 1e-12);
    compare_with_serial(scene, true, false, false, 1, 2e-11, false, true, nullptr, Run::Split::balanced);
}

// Resuming keeps the scene's last forces: a scene that has none (never prepared) or whose forces
// belong to another law is refused, not run from zero or stale forces.
BOOST_AUTO_TEST_CASE(a_scene_without_its_present_forces_cannot_resume) {
    auto serial = lattice<2>(per_side(2), 10e-6);
    using Run = mm::mpi::DistributedRun<decltype(serial)>;
    mmtest::expect_error([&] { Run run(MPI_COMM_WORLD, serial, Run::Start::resume); }, {"Start::resume", "prepare()", "Start::fresh"});
    serial.run(10);
    serial.law().tangential = mm::CundallStrack(serial.law().tangential.stiffness(), 0.0, 0.3);
    mmtest::expect_error([&] { Run run(MPI_COMM_WORLD, serial, Run::Start::resume); }, {"Start::resume", "law"});
    serial.prepare();
    Run run(MPI_COMM_WORLD, serial, Run::Start::resume);  // its forces are the present scene's again
    BOOST_TEST(run.steps_done() == 10u);
}

BOOST_AUTO_TEST_CASE(a_share_cannot_resume) {
    auto serial = lattice<2>(per_side(2), 10e-6);
    using Run = mm::mpi::DistributedRun<decltype(serial)>;
    mmtest::expect_error([&] { Run run(MPI_COMM_WORLD, share_of(serial), Run::Start::resume, Run::Input::share); },
                         {"resumed run", "Input::whole"});
}

// Ranks x threads: two OpenMP threads in each rank's engine and in the serial run (8 100 disks, so
// that two ranks hold enough particles for both threads), the serial state to round-off. In this
// larger packing round-off grows further over the 200 steps: the serial run numbered backwards
// differs by up to 8.1e-12, 1-4 ranks by up to 1.7e-11; a contact missed would be off by its share.
BOOST_AUTO_TEST_CASE(threads_within_ranks_keep_the_serial_state) {
#ifdef _OPENMP
    compare_with_serial(lattice<2>(90, 0.5e-3), false, false, false, 2, 1e-10);
#else
    BOOST_TEST_MESSAGE("built without OpenMP: one thread per rank");
#endif
}

// Rows of particles along the first axis, each touching its two neighbours in its row (rows too
// far apart to touch), drifting along the rows at 2 m/s with small random velocities and spins:
// a particle has two contacts, whose forces add to the same sum in either order, so the run on
// any number of ranks must give the serial bits where a rank measures each pair and wraps each
// particle as the serial engine does: pairs across the periodic boundary between ranks
// by the minimum image, particles wrapped in the step they cross it (some sit 50 um before it),
// handed to new ranks every few steps (a skin of 10 um). Without fused multiply-adds the bits; with
// them round-off is promised (see compare_with_serial).
BOOST_AUTO_TEST_CASE_TEMPLATE(pairs_across_rank_and_periodic_boundaries_give_the_serial_bits, D, Dims) {
    constexpr int dim = D::value;
    const int along = 20, rows = dim == 2 ? 6 : 4;
    const double spacing = 1.99e-3, row_spacing = 3.3e-3;
    mm::Vec<dim> hi = mm::Vec<dim>::Constant(rows * row_spacing);
    hi[0] = along * spacing;
    mm::BasicSimulation<dim, double, mm::FrictionalLinear> serial(mmtest::lattice_law,
                                                                  mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), hi));
    std::mt19937_64 rng(31);
    std::normal_distribution<double> N(0.0, 1.0);
    for (int row = 0; row < (dim == 2 ? rows : rows * rows); ++row)
        for (int k = 0; k < along; ++k) {
            mm::Vec<dim> x;
            x[0] = k == 0 ? hi[0] - 50e-6 : k * spacing - 50e-6;
            x[1] = (row % rows + 0.5) * row_spacing;
            if constexpr (dim == 3) x[2] = (row / rows + 0.5) * row_spacing;
            const std::size_t i = serial.particles().add(x, 1e-3, mm::sphere_mass(mmtest::rho, 1e-3));
            for (int a = 0; a < dim; ++a) serial.particles().velocity()[i][a] = (a == 0 ? 2.0 : 0.0) + 0.05 * N(rng);
            auto& w = serial.particles().template get<mm::field::AngularVelocity>()[i];
            if constexpr (dim == 2) w = 20.0 * N(rng);
            else w = mm::Vec<3>(20.0 * N(rng), 20.0 * N(rng), 20.0 * N(rng));
        }
    serial.set_time_step(mm::contact_duration(mmtest::k, mmtest::gamma0, mm::sphere_mass(mmtest::rho, 1e-3) / 2) / 50);
    serial.set_skin(10e-6);
    mm::mpi::DistributedRun distributed(MPI_COMM_WORLD, serial);
    serial.prepare();
    const auto& s = serial.particles();
    const auto by_id = s.index_by_id();
    std::size_t wrapped = 0;  // particles that crossed the periodic boundary, seen at comparisons
    for (int step = 1; step <= 200; ++step) {
        serial.step();
        distributed.step();
        const auto& p = distributed.local().particles();
        const auto& w = s.template get<mm::field::AngularVelocity>();
        const auto& t = s.template get<mm::field::Torque>();
        double w_scale = 0.0, t_scale = 0.0;  // the largest values, for relative differences
        for (std::size_t k = 0; k < s.size(); ++k) w_scale = std::max(w_scale, norm<dim>(w[k])), t_scale = std::max(t_scale, norm<dim>(t[k]));
        const double v_scale = largest<dim>(s.velocity()), f_scale = largest<dim>(s.force());
        double worst = 0.0;
        for (std::size_t i = 0; i < distributed.owned(); ++i) {
            const std::size_t k = by_id[distributed.global_id(i)];
            const auto dw = p.template get<mm::field::AngularVelocity>()[i] - w[k];
            const auto dt = p.template get<mm::field::Torque>()[i] - t[k];
            worst = std::max({worst, (p.position()[i] - s.position()[k]).norm() / hi.norm(), (p.velocity()[i] - s.velocity()[k]).norm() / v_scale,
                              (p.force()[i] - s.force()[k]).norm() / f_scale, norm<dim>(dw) / w_scale, norm<dim>(dt) / t_scale});
            wrapped += s.position()[k][0] < 0.5 * spacing && step % 50 == 0;
        }
#ifdef MICROMACRO_FP_CONTRACT
        BOOST_TEST(worst < 1e-12, "rank " << distributed.comm().rank() << ", step " << step << ": relative difference " << worst);
#else
        BOOST_TEST(worst == 0.0, "rank " << distributed.comm().rank() << ", step " << step << ": relative difference " << worst);
#endif
    }
    unsigned long long here = wrapped, all = 0;
    MPI_Allreduce(&here, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    BOOST_TEST(all > 0u, "no particle crossed the periodic boundary");
    BOOST_TEST(distributed.redistributions() > 20u);
    std::size_t contacts = 0;
    serial.for_each_contact([&](const auto&) { ++contacts; });
    BOOST_TEST(contacts == s.size(), "every particle keeps its two contacts");
}

BOOST_AUTO_TEST_SUITE_END()
