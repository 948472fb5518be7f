// Parallel VTK output (mpi::write_particles) under mpirun with 1 and 3 ranks: the pieces and
// their summary, read back by VTK's reader of .pvtp files (the one ParaView uses), hold every
// particle of the scene once, each with the serial run's position, velocity, radius and
// coordination to round-off, found by its global id; the frame's own numbers travel as field
// data; a summary without the .pvtp extension and an unwritable folder are refused on every
// rank. The contacts (mpi::write_contacts) read back as the serial run's, each once, in a periodic
// box and in a box of walls. In 2D and 3D.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPPolyDataReader.h>

#include <micromacro/mpi/vtk_output.hpp>

#include "support/mpi_lattice.hpp"
#include "support/mpi_runtime.hpp"

BOOST_AUTO_TEST_SUITE(mpi_vtk_output)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
using mmtest::Dims;

BOOST_AUTO_TEST_CASE_TEMPLATE(pieces_read_back_as_the_whole_scene, D, Dims) {
    constexpr int dim = D::value;
    const int rank = mmtest::world_rank(), ranks = mmtest::world_size();
    auto serial = mmtest::lattice<dim>(dim == 2 ? 18 : 8, 10e-6);
    mm::mpi::DistributedRun run(MPI_COMM_WORLD, serial);
    serial.prepare();
    serial.run(30);
    run.run(30);
    const auto dir = std::filesystem::temp_directory_path() / ("micromacro_pvtp_" + std::to_string(dim) + "d_" + std::to_string(ranks));
    if (rank == 0) std::filesystem::create_directories(dir);
    MPI_Barrier(MPI_COMM_WORLD);
    const auto summary = dir / "particles_0001.pvtp";
    mm::mpi::write_particles(run, summary, {{"eps_zz", 0.25}});

    vtkNew<vtkXMLPPolyDataReader> reader;
    reader->SetFileName(summary.string().c_str());
    reader->Update();
    vtkPolyData* data = reader->GetOutput();
    const auto& s = serial.particles();
    BOOST_TEST_REQUIRE(data->GetNumberOfPoints() == static_cast<vtkIdType>(s.size()));
    auto* pd = data->GetPointData();
    auto* id = vtkIdTypeArray::SafeDownCast(pd->GetArray("id"));
    auto* coordination = vtkIntArray::SafeDownCast(pd->GetArray("coordination"));
    vtkDataArray* velocity = pd->GetArray("velocity");
    vtkDataArray* radius = pd->GetArray("radius");
    BOOST_TEST_REQUIRE((id && coordination && velocity && radius));
    // Every particle once, by id, at the serial run's state.
    std::vector<int> contacts(s.size(), 0);
    serial.for_each_contact([&](const auto& c) {
        ++contacts[c.i];
        if (!c.wall) ++contacts[c.j];
    });
    std::vector<int> seen(s.size(), 0);
    double dx = 0, dv = 0, v_scale = 0;
    int coordination_differs = 0;
    for (std::size_t i = 0; i < s.size(); ++i) v_scale = std::max(v_scale, s.velocity()[i].norm());
    for (vtkIdType k = 0; k < data->GetNumberOfPoints(); ++k) {
        const auto g = static_cast<std::size_t>(id->GetValue(k));
        BOOST_TEST_REQUIRE(g < s.size());
        ++seen[g];
        double x[3], v[3];
        data->GetPoint(k, x);
        velocity->GetTuple(k, v);
        mm::Vec<dim> xv, vv;
        for (int a = 0; a < dim; ++a) xv[a] = x[a], vv[a] = v[a];
        dx = std::max(dx, serial.domain().separation(xv, s.position()[g]).norm() / 1e-3);
        dv = std::max(dv, (vv - s.velocity()[g]).norm() / v_scale);
        coordination_differs += coordination->GetValue(k) != contacts[g];
        BOOST_TEST_REQUIRE(radius->GetTuple1(k) == s.radius()[g]);
    }
    BOOST_TEST(std::count(seen.begin(), seen.end(), 1) == static_cast<long>(s.size()));
    BOOST_TEST_MESSAGE(dim << "D, " << ranks << " ranks: positions within " << dx << " of a radius, velocities " << dv);
    BOOST_TEST(dx < 2e-11);
    BOOST_TEST(dv < 2e-11);
    BOOST_TEST(coordination_differs == 0);
    auto* eps = data->GetFieldData()->GetArray("eps_zz");
    BOOST_TEST_REQUIRE(eps);
    BOOST_TEST(eps->GetTuple1(0) == 0.25);

    // Refusals, on every rank alike.
    BOOST_CHECK_THROW(mm::mpi::write_particles(run, dir / "particles.vtp"), mm::InputError);
    BOOST_CHECK_THROW(mm::mpi::write_particles(run, dir / "missing" / "particles.pvtp"), mm::InputError);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) std::filesystem::remove_all(dir);
}

// Every contact once: as many lines as the serial run has contacts, with its normal forces (sorted,
// to round-off) and its sliding contacts.
template <class Sim>
void check_contacts(Sim serial, const std::string& name) {
    constexpr int dim = Sim::dimension;
    const int rank = mmtest::world_rank(), ranks = mmtest::world_size();
    serial.set_track_energy(false);  // as the distributed run (see tests/mpi/distributed_run.cpp)
    mm::mpi::DistributedRun run(MPI_COMM_WORLD, serial);
    serial.prepare();
    serial.run(30);
    run.run(30);
    const auto dir = std::filesystem::temp_directory_path() / ("micromacro_contacts_" + name + std::to_string(dim) + "d_" + std::to_string(ranks));
    if (rank == 0) std::filesystem::create_directories(dir);
    MPI_Barrier(MPI_COMM_WORLD);
    const auto summary = dir / "contacts_0001.pvtp";
    mm::mpi::write_contacts(run, summary);
    vtkNew<vtkXMLPPolyDataReader> reader;
    reader->SetFileName(summary.string().c_str());
    reader->Update();
    vtkPolyData* data = reader->GetOutput();
    std::vector<double> expected;
    std::size_t expected_walls = 0, expected_sliding = 0;
    serial.for_each_contact([&](const auto& c) {
        expected.push_back(c.normal_force);
        expected_walls += c.wall;
        expected_sliding += c.sliding;
    });
    BOOST_TEST_REQUIRE(data->GetNumberOfLines() == static_cast<vtkIdType>(expected.size()));
    auto* normal = data->GetCellData()->GetArray("normal_force");
    auto* sliding = data->GetCellData()->GetArray("sliding");
    BOOST_TEST_REQUIRE((normal && sliding));
    std::vector<double> read;
    std::size_t read_sliding = 0;
    for (vtkIdType q = 0; q < data->GetNumberOfCells(); ++q) {
        read.push_back(normal->GetTuple1(q));
        read_sliding += sliding->GetTuple1(q) != 0.0;
    }
    std::sort(expected.begin(), expected.end());
    std::sort(read.begin(), read.end());
    double worst = 0.0;
    for (std::size_t q = 0; q < read.size(); ++q) worst = std::max(worst, std::abs(read[q] - expected[q]) / expected.back());
    BOOST_TEST_MESSAGE(dim << "D, " << name << ranks << " ranks: " << read.size() << " contacts (" << expected_walls << " on walls), normal forces within " << worst);
    BOOST_TEST(worst < 2e-11);
    BOOST_TEST(read_sliding == expected_sliding);
    if constexpr (Sim::has_walls) BOOST_TEST(expected_walls > 0u);
    BOOST_CHECK_THROW(mm::mpi::write_contacts(run, dir / "contacts.vtp"), mm::InputError);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) std::filesystem::remove_all(dir);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(contact_pieces_read_back_as_the_whole_network, D, Dims) {
    check_contacts(mmtest::lattice<D::value>(D::value == 2 ? 18 : 8, 10e-6), "periodic_");
    check_contacts(mmtest::walled_lattice<D::value>(D::value == 2 ? 19 : 7, 10e-6, true), "walls_");
}

BOOST_AUTO_TEST_SUITE_END()
