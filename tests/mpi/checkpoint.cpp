// Checkpoints across rank counts (mpi/checkpoint.hpp) under mpirun with 1-4 ranks: a run of the
// MPI tests' frictional packing stopped after 50 steps is gathered into one serial scene
// (whole_scene), written to a state file and read back; from it the run goes on for 50 steps
// over all the ranks, over rank 0 alone, and in the serial engine, and each ends where the serial
// run of 100 steps ends, to round-off (the particles handed to new ranks on the way: a 10 um
// skin). On one rank every copy gives the serial run's bits. In 2D and 3D, in the periodic box and
// in the box of moving walls, whose walls and wall contacts' springs the checkpoint carries.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>

#include <micromacro/io/state.hpp>
#include <micromacro/mpi/checkpoint.hpp>
#include <micromacro/mpi/energy.hpp>

#include "support/mpi_compare.hpp"
#include "support/mpi_lattice.hpp"
#include "support/mpi_runtime.hpp"

BOOST_AUTO_TEST_SUITE(mpi_checkpoint)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
using mmtest::Dims;

namespace {
using mmtest::from_distributed;

template <class Sim>
double from_serial(const Sim& serial, const Sim& other) {
    const auto& p = other.particles();
    return mmtest::largest_difference(serial, p.size(), [&](std::size_t i) {
        return std::tuple{static_cast<std::size_t>(p.id(i)), p.position()[i], p.velocity()[i],
                          p.template get<mm::field::AngularVelocity>()[i], p.force()[i], p.template get<mm::field::Torque>()[i]};
    });
}
}  // namespace

// Returns how often the serial engine sorted its particles between the checkpoint and the end.
template <class Sim>
std::size_t check_restarts(Sim serial, const std::string& name) {
    constexpr int dim = Sim::dimension;
    const int rank = mmtest::world_rank(), ranks = mmtest::world_size();
    mm::mpi::DistributedRun first(MPI_COMM_WORLD, serial);
    serial.prepare();
    first.run(50);
    Sim gathered = mm::mpi::whole_scene(first);
    BOOST_TEST(gathered.steps_done() == 50u);
    BOOST_TEST(gathered.time() == first.time());

    // Written by rank 0 and read by every rank.
    const auto file = std::filesystem::temp_directory_path() /
                      ("micromacro_checkpoint_" + name + std::to_string(dim) + "d_" + std::to_string(ranks) + "_ranks.state");
    if (rank == 0) mm::io::save_state(gathered, file, {}, "checkpoint");
    MPI_Barrier(MPI_COMM_WORLD);
    Sim restored = gathered;  // overwritten by the file
    mm::io::load_state(restored, file, "checkpoint");
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) std::filesystem::remove(file);
    BOOST_TEST(restored.steps_done() == 50u);

    serial.run(50);
    const std::size_t sorts_at_checkpoint = serial.spatial_sorts();  // the engine's sorts (from 2048 particles on)
    BOOST_TEST(first.spatial_sorts() == sorts_at_checkpoint);
    serial.run(50);
    const std::size_t sorts_after = serial.spatial_sorts() - sorts_at_checkpoint;
    // On all ranks.
    mm::mpi::DistributedRun again(MPI_COMM_WORLD, restored, mm::mpi::DistributedRun<Sim>::Start::resume);
    again.run(50);
    BOOST_TEST(again.steps_done() == 100u);
    BOOST_TEST(again.spatial_sorts() - restored.spatial_sorts() == sorts_after);
    const double on_all = from_distributed(serial, again);
    // The books went through the checkpoint: each entry against the serial run's, relative to the
    // total energy (a book lost or counted on every rank would be off by its whole value).
    const auto books_gap = [&](const mm::EnergyBooks& b, double initial) {
        const mm::EnergyBooks& s = serial.books();
        const double scale = serial.energy().total();
        double d = std::abs(initial - serial.initial_energy());
        for (const auto& [x, y] : {std::pair{b.dissipated_normal, s.dissipated_normal}, {b.dissipated_tangential, s.dissipated_tangential},
                                   {b.dissipated_sliding, s.dissipated_sliding}, {b.dissipated_background, s.dissipated_background},
                                   {b.dissipated_walls, s.dissipated_walls}, {b.work_by_walls, s.work_by_walls}})
            d = std::max(d, std::abs(x - y));
        return d / scale;
    };
    BOOST_TEST_REQUIRE(serial.books().dissipated() > 0.0);
    const mm::OpenBooks all_books = mm::mpi::open_books(again);
    const double books_on_all = books_gap(all_books.books, all_books.initial_energy);
    // On rank 0 alone, and in the serial engine.
    double on_one = 0.0, in_serial = 0.0, books_on_one = 0.0, books_in_serial = 0.0;
    MPI_Comm alone;
    MPI_Comm_split(MPI_COMM_WORLD, rank == 0 ? 0 : MPI_UNDEFINED, 0, &alone);
    if (rank == 0) {
        mm::mpi::DistributedRun single(alone, restored, mm::mpi::DistributedRun<Sim>::Start::resume);
        single.run(50);
        BOOST_TEST(single.spatial_sorts() - restored.spatial_sorts() == sorts_after);
        on_one = from_distributed(serial, single);
        const mm::OpenBooks one_books = mm::mpi::open_books(single);
        books_on_one = books_gap(one_books.books, one_books.initial_energy);
        MPI_Comm_free(&alone);
        Sim continued = restored;
        continued.run(50);
        BOOST_TEST(continued.spatial_sorts() - restored.spatial_sorts() == sorts_after);
        in_serial = from_serial(serial, continued);
        books_in_serial = books_gap(continued.books(), continued.initial_energy());
    }
    BOOST_TEST_MESSAGE(dim << "D, rank " << rank << " of " << ranks << ", after 100 steps with a checkpoint at 50, largest relative "
                           << "difference from the serial run: over all ranks " << on_all << ", over rank 0 alone " << on_one
                           << ", serially " << in_serial << "; " << first.redistributions() + again.redistributions()
                           << " redistributions; books " << books_on_all << ", " << books_on_one << ", " << books_in_serial);
    // The distributed runs' round-off (tests/mpi/distributed_run.cpp): within 2e-11. A spring, a
    // force or a torque lost in the checkpoint would be off by a contact's share, orders more.
    const double round_off = 2e-11;
    BOOST_TEST(on_all < round_off);
    BOOST_TEST(on_one < round_off);
    BOOST_TEST(in_serial < round_off);
    BOOST_TEST(books_on_all < round_off);
    BOOST_TEST(books_on_one < round_off);
    BOOST_TEST(books_in_serial < round_off);
    if (ranks == 1) BOOST_TEST((on_all == 0.0 && on_one == 0.0 && in_serial == 0.0), "one rank gives the serial bits");
    BOOST_TEST(first.redistributions() + again.redistributions() > 0u);
    if constexpr (Sim::has_walls) {  // the walls where the serial run's are
        double dh = 0.0;
        for (std::size_t k = 0; k < serial.walls().size(); ++k)
            dh = std::max(dh, std::abs(again.local().walls()[k].offset - serial.walls()[k].offset) / 1e-3);
        BOOST_TEST(dh < round_off, "walls off by " << dh << " of a radius");
        BOOST_TEST(std::abs(serial.walls()[2 * dim - 1].offset - serial.walls()[2 * dim - 1].initial_offset) > 1e-6);
    }
    return sorts_after;
}

BOOST_AUTO_TEST_CASE_TEMPLATE(a_checkpoint_restarts_on_any_rank_count, D, Dims) {
    check_restarts(mmtest::lattice<D::value>(D::value == 2 ? 18 : 8, 10e-6), "periodic_");
}

// The checkpoint carries the serial engine's sorting and neighbour-list references: a scene large
// enough to be sorted (mpi_lattice.hpp), sorted again between the checkpoint and the end, ends
// there with the serial run's particles in every copy, sorted as often.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_checkpoint_keeps_the_serial_sorting, D, Dims) {
    BOOST_TEST(check_restarts(mmtest::sorting_lattice<D::value>(std::pair{50, 100}), "sorting_") == 1u);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(a_checkpoint_of_a_box_of_walls_restarts_on_any_rank_count, D, Dims) {
    check_restarts(mmtest::walled_lattice<D::value>(D::value == 2 ? 19 : 7, 10e-6, true), "walls_");
}

BOOST_AUTO_TEST_SUITE_END()
