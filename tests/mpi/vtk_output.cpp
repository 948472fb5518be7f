// Parallel VTK output (mpi::write_particles) under mpirun with 1 and 3 ranks: the pieces and
// their summary, read back by VTK's reader of .pvtp files (the one ParaView uses), hold every
// particle of the scene once, each with the serial run's position, velocity, radius and
// coordination to round-off, found by its global id; the frame's own numbers travel as field
// data; a summary without the .pvtp extension and an unwritable folder are refused on every
// rank. In 2D and 3D.
#define BOOST_TEST_MODULE mpi_vtk_output
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <string>

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

namespace mm = micromacro;
using mmtest::Dims;

using mmtest::MpiRuntime;
BOOST_TEST_GLOBAL_FIXTURE(MpiRuntime);

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
