// VTK writers: a known configuration written and read back with VTK's own XML readers gives every
// array exactly, in 2D (plane z = 0) and 3D; the .pvd lists the times; errors for missing
// directories; no partial files left.
#define BOOST_TEST_MODULE io_vtk_round_trip
#include <boost/test/unit_test.hpp>

#include <filesystem>

#include <micromacro/io/vtk.hpp>
#include <vtkXMLPolyDataReader.h>

#include "support/programs.hpp"
#include "support/scenes.hpp"

using namespace mmtest;
namespace fs = std::filesystem;

namespace {
vtkSmartPointer<vtkPolyData> read(const fs::path& p) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(p.string().c_str());
    reader->Update();
    return reader->GetOutput();
}

template <int dim>
auto frictional_scene() {
    using Sim = mm::Simulation<dim, mm::FrictionalLinear, mm::Walls<dim>>;
    mm::Walls<dim> walls;
    const double L = dim == 2 ? 0.012 : 0.006;
    walls.add_box(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L));
    Sim sim(mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)}, {}, walls);
    const auto p = random_packing<dim>(dim == 2 ? 40 : 60, 0.5e-3, 1.5e-3, L, 3, true, false);
    for (std::size_t i = 0; i < p.x.size(); ++i) {
        sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
        sim.particles().velocity()[i] = mm::Vec<dim>::Constant(0.01 * double(i % 5));
    }
    sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, 0.5e-3) / 2) / 50);
    sim.run(200);
    return sim;
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(particles_contacts_walls_round_trip, D, Dims) {
    constexpr int dim = D::value;
    const fs::path dir = fs::temp_directory_path() / ("micromacro_vtk_" + std::to_string(dim));
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto sim = frictional_scene<dim>();
    const auto frame = mm::io::particle_frame(sim);
    const auto snapshot = mm::take_snapshot(sim);
    mm::io::write_particles(frame, dir / "particles_0.vtp");
    mm::io::write_contacts(snapshot, dir / "contacts_0.vtp");
    mm::io::write_walls(snapshot, dir / "walls_0.vtp");
    mm::io::PvdCollection pvd(dir / "particles.pvd");
    pvd.add(sim.time(), dir / "particles_0.vtp");
    pvd.write();
    for (const auto& entry : fs::directory_iterator(dir)) BOOST_TEST(entry.path().extension() != ".partial");

    const auto particles = read(dir / "particles_0.vtp");
    BOOST_TEST_REQUIRE(particles->GetNumberOfPoints() == static_cast<vtkIdType>(frame.position.size()));
    auto* pd = particles->GetPointData();
    bool exact = true;
    for (vtkIdType i = 0; i < particles->GetNumberOfPoints(); ++i) {
        double x[3];
        particles->GetPoint(i, x);
        const auto& r = frame.position[static_cast<std::size_t>(i)];
        exact &= x[0] == r[0] && x[1] == r[1] && x[2] == (dim == 3 ? r[2] : 0.0);
        exact &= pd->GetArray("radius")->GetTuple1(i) == frame.radius[static_cast<std::size_t>(i)];
        exact &= pd->GetArray("potential_energy")->GetTuple1(i) == frame.potential_energy[static_cast<std::size_t>(i)];
        exact &= pd->GetArray("kinetic_energy")->GetTuple1(i) == frame.kinetic_energy[static_cast<std::size_t>(i)];
        exact &= pd->GetArray("coordination")->GetTuple1(i) == frame.coordination[static_cast<std::size_t>(i)];
        const double* v = pd->GetArray("velocity")->GetTuple3(i);
        exact &= v[0] == frame.velocity[static_cast<std::size_t>(i)][0] && v[1] == frame.velocity[static_cast<std::size_t>(i)][1];
        const double* w = pd->GetArray("angular_velocity")->GetTuple3(i);
        exact &= w[2] == frame.angular_velocity[static_cast<std::size_t>(i)][2];
        const double* s = pd->GetArray("stress")->GetTuple9(i);
        exact &= s[1] == frame.stress[static_cast<std::size_t>(i)](0, 1);
    }
    BOOST_TEST(exact);
    // Potential energies add up to the elastic energy (each spring split between partners).
    double sum = 0.0;
    for (double u : frame.potential_energy) sum += u;
    const auto e = sim.energy();
    BOOST_TEST(std::abs(sum - (e.elastic_normal + e.elastic_tangential)) <= 1e-12 * sum);
    BOOST_TEST(sum > 0.0);

    const auto contacts = read(dir / "contacts_0.vtp");
    BOOST_TEST_REQUIRE(contacts->GetNumberOfCells() == static_cast<vtkIdType>(snapshot.contacts.size()));
    bool contacts_exact = true;
    for (vtkIdType q = 0; q < contacts->GetNumberOfCells(); ++q) {
        const auto& c = snapshot.contacts[static_cast<std::size_t>(q)];
        contacts_exact &= contacts->GetCellData()->GetArray("normal_force")->GetTuple1(q) == c.normal_force;
        contacts_exact &= contacts->GetCellData()->GetArray("overlap")->GetTuple1(q) == c.overlap;
        contacts_exact &= contacts->GetCellData()->GetArray("tangential_force")->GetTuple3(q)[0] == c.tangential_force[0];
    }
    BOOST_TEST(contacts_exact);
    const auto walls = read(dir / "walls_0.vtp");
    BOOST_TEST(walls->GetNumberOfCells() == 2 * dim);
    BOOST_TEST(walls->GetCellData()->GetArray("force")->GetTuple3(0)[0] == snapshot.walls[0].force[0]);
    const std::string collection = slurp(dir / "particles.pvd");
    BOOST_TEST(collection.find("file=\"particles_0.vtp\"") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(missing_directory_is_an_error) {
    auto sim = frictional_scene<2>();
    try {
        mm::io::write_particles(mm::io::particle_frame(sim), "/nonexistent/dir/p.vtp");
        BOOST_ERROR("wrote into a missing directory");
    } catch (const mm::InputError& e) {
        BOOST_TEST(std::string(e.what()).find("the directory /nonexistent/dir does not exist") != std::string::npos, e.what());
    }
}
