// VTK writers: a known configuration written and read back with VTK's own XML readers gives every
// array exactly, in 2D (plane z = 0) and 3D; the .pvd lists the times; errors for missing
// directories and a full disk; no partial files left.
#define BOOST_TEST_MODULE io_vtk_round_trip
#include <boost/test/unit_test.hpp>

#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <numeric>

#include <micromacro/io/vtk.hpp>
#include <vtkCell.h>
#include <vtkFieldData.h>
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
    std::vector<mm::Index> reversed(sim.particles().size());
    std::iota(reversed.rbegin(), reversed.rend(), mm::Index{0});
    sim.renumber(reversed);  // the ids then differ from the indices
    auto frame = mm::io::particle_frame(sim);
    frame.values = {{"eps_zz", 0.1 / 3.0}, {"time", 2.5}};  // the frame's own numbers, as field data
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
    // Every component of every array, exactly.
    auto same = [](vtkDataArray* a, vtkIdType i, std::initializer_list<double> want) {
        if (!a || a->GetNumberOfComponents() != static_cast<int>(want.size())) return false;
        int k = 0;
        for (double w : want)
            if (a->GetComponent(i, k++) != w) return false;
        return true;
    };
    auto xyz = [](const mm::Vec<dim>& v) { return std::array<double, 3>{v[0], v[1], dim == 3 ? v[dim - 1] : 0.0}; };
    bool exact = true;
    for (vtkIdType i = 0; i < particles->GetNumberOfPoints(); ++i) {
        const auto n = static_cast<std::size_t>(i);
        double x[3];
        particles->GetPoint(i, x);
        const auto p = xyz(frame.position[n]), v = xyz(frame.velocity[n]), f = xyz(frame.force[n]);
        const auto& w = frame.angular_velocity[n];
        exact &= x[0] == p[0] && x[1] == p[1] && x[2] == p[2];
        exact &= same(pd->GetArray("radius"), i, {frame.radius[n]});
        exact &= same(pd->GetArray("potential_energy"), i, {frame.potential_energy[n]});
        exact &= same(pd->GetArray("kinetic_energy"), i, {frame.kinetic_energy[n]});
        exact &= same(pd->GetArray("coordination"), i, {double(frame.coordination[n])});
        exact &= same(pd->GetArray("id"), i, {double(frame.position.size() - 1 - n)});
        exact &= same(pd->GetArray("velocity"), i, {v[0], v[1], v[2]});
        exact &= same(pd->GetArray("force"), i, {f[0], f[1], f[2]});
        exact &= same(pd->GetArray("angular_velocity"), i, {w[0], w[1], w[2]});
        const auto& t = frame.stress[n];
        auto T = [&](int a, int b) { return a < dim && b < dim ? t(a, b) : 0.0; };
        exact &= same(pd->GetArray("stress"), i, {T(0, 0), T(0, 1), T(0, 2), T(1, 0), T(1, 1), T(1, 2), T(2, 0), T(2, 1), T(2, 2)});
    }
    BOOST_TEST(exact);
    auto* fields = particles->GetFieldData();
    for (const auto& [name, value] : frame.values) {
        auto* a = fields->GetArray(name.c_str());
        BOOST_TEST_REQUIRE(a, name);
        BOOST_TEST((a->GetNumberOfTuples() == 1 && a->GetTuple1(0) == value), name);
    }
    // Potential energies add up to the elastic energy (each spring split between partners).
    double sum = 0.0;
    for (double u : frame.potential_energy) sum += u;
    const auto e = sim.energy();
    BOOST_TEST(std::abs(sum - (e.elastic_normal + e.elastic_tangential)) <= 1e-12 * sum);
    BOOST_TEST(sum > 0.0);

    const auto contacts = read(dir / "contacts_0.vtp");
    BOOST_TEST_REQUIRE(contacts->GetNumberOfCells() == static_cast<vtkIdType>(snapshot.contacts.size()));
    bool contacts_exact = true;
    auto* cd = contacts->GetCellData();
    for (vtkIdType q = 0; q < contacts->GetNumberOfCells(); ++q) {
        const auto& c = snapshot.contacts[static_cast<std::size_t>(q)];
        const auto t = xyz(c.tangential_force);
        contacts_exact &= same(cd->GetArray("normal_force"), q, {c.normal_force});
        contacts_exact &= same(cd->GetArray("overlap"), q, {c.overlap});
        contacts_exact &= same(cd->GetArray("sliding"), q, {c.sliding ? 1.0 : 0.0});
        contacts_exact &= same(cd->GetArray("tangential_force"), q, {t[0], t[1], t[2]});
        // The line joins i's centre to the partner as the branch sees it.
        double a[3], b[3];
        contacts->GetPoint(contacts->GetCell(q)->GetPointId(0), a);
        contacts->GetPoint(contacts->GetCell(q)->GetPointId(1), b);
        const auto end = xyz(mm::Vec<dim>(snapshot.position[c.i] - c.branch));
        contacts_exact &= a[0] == xyz(snapshot.position[c.i])[0] && b[0] == end[0] && b[1] == end[1] && b[2] == end[2];
    }
    BOOST_TEST(contacts_exact);
    const auto walls = read(dir / "walls_0.vtp");
    BOOST_TEST(walls->GetNumberOfCells() == 2 * dim);
    for (vtkIdType w = 0; w < walls->GetNumberOfCells(); ++w) {
        const auto f = xyz(snapshot.walls[static_cast<std::size_t>(w)].force);
        BOOST_TEST(same(walls->GetCellData()->GetArray("force"), w, {f[0], f[1], f[2]}));
    }
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

// A full disk, as a file-size limit (RLIMIT_FSIZE with SIGXFSZ ignored: writes past the limit
// fail with EFBIG, as on a full disk): VTK's writer leaves a truncated file and may still return
// success, so the error code decides. The frame and the collection are refused with a message,
// and neither a truncated file under its final name nor a .partial is left.
BOOST_AUTO_TEST_CASE(full_disk_leaves_no_file) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_vtk_full";
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto sim = frictional_scene<3>();
    const auto frame = mm::io::particle_frame(sim);
    rlimit before{};
    getrlimit(RLIMIT_FSIZE, &before);
    const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit tiny = before;
    tiny.rlim_cur = 512;  // bytes: less than the frame's header
    BOOST_REQUIRE(setrlimit(RLIMIT_FSIZE, &tiny) == 0);
    std::string particles_error, pvd_error;
    try {
        mm::io::write_particles(frame, dir / "particles_0.vtp");
    } catch (const mm::InputError& e) {
        particles_error = e.what();
    }
    try {
        mm::io::PvdCollection pvd(dir / "particles.pvd");
        for (int f = 0; f < 40; ++f) pvd.add(0.001 * f, "particles_" + std::to_string(f) + ".vtp");  // over 512 bytes
        pvd.write();
    } catch (const mm::InputError& e) {
        pvd_error = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &before);
    std::signal(SIGXFSZ, old_handler);
    BOOST_TEST(particles_error.find("cannot write " + (dir / "particles_0.vtp").string()) != std::string::npos, particles_error);
    BOOST_TEST(pvd_error.find("cannot write") != std::string::npos, pvd_error);
    BOOST_TEST(fs::is_empty(dir));  // no truncated frame, no collection, no .partial
}
