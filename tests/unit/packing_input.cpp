// Reading a packing file's format, dimension, box and periodic axes (io/packing_files.hpp): the
// one place the programs that take a packing file (analyze_packing, throughput) settle them; and
// the LAMMPS dump the writer makes (io/packing_writer.hpp) reads back to the last digit.
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <micromacro/io/packing_files.hpp>
#include <micromacro/io/packing_writer.hpp>

#include "support/programs.hpp"

BOOST_AUTO_TEST_SUITE(unit_packing_input)  // the file's cases, run as the CTest test of this file's name

namespace fs = std::filesystem;
namespace mm = micromacro;
namespace io = micromacro::io;

namespace {
std::string write(const std::string& name, const std::string& text) {
    return mmtest::write_file(fs::temp_directory_path() / "micromacro_packing_input_test", name, text);
}

template <class F>
std::string message_of(F&& f) {
    try {
        f();
    } catch (const mm::InputError& e) {
        return e.what();
    }
    return "no error";
}
}  // namespace

BOOST_AUTO_TEST_CASE(format_and_dimension_from_the_file) {
    const auto csv2 = write("a.csv", "# a comment first\n\nid,x,z,r\n1,0,0,1e-3\n");
    const auto csv3 = write("b.csv", "x, y, z, radius\n0,0,0,1e-3\n");
    const auto dump = write("c.dump", "ITEM: TIMESTEP\n0\n");
    BOOST_TEST((io::guess_format(csv2) == io::PackingFormat::csv));
    BOOST_TEST((io::guess_format(dump) == io::PackingFormat::lammps_dump));
    BOOST_TEST(io::guess_dimension(csv2, io::PackingFormat::csv) == 2);
    BOOST_TEST(io::guess_dimension(csv3, io::PackingFormat::csv) == 3);  // names trimmed of spaces
    BOOST_TEST(io::guess_dimension(dump, io::PackingFormat::lammps_dump) == 3);
    BOOST_TEST(message_of([] { io::guess_format("/nonexistent/packing.csv"); }).find("cannot open") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(periodic_axes_by_name) {
    BOOST_TEST((io::parse_periodic_axes<2>("x,z") == std::array<bool, 2>{true, true}));
    BOOST_TEST((io::parse_periodic_axes<2>("z") == std::array<bool, 2>{false, true}));
    BOOST_TEST((io::parse_periodic_axes<3>("x y") == std::array<bool, 3>{true, true, false}));
    BOOST_TEST((io::parse_periodic_axes<3>("") == std::array<bool, 3>{false, false, false}));
    // 2D is the paper's (x, z) plane: y is not one of its axes.
    BOOST_TEST(message_of([] { io::parse_periodic_axes<2>("x,y"); }) ==
               "periodic axes 'x,y': unknown axis 'y'; in 2D name them from x, z (for example x,z)");
    BOOST_TEST(message_of([] { io::parse_periodic_axes<3>("xq"); }).find("unknown axis 'q'; in 3D name them from x, y, z") !=
               std::string::npos);
}

BOOST_AUTO_TEST_CASE(box_from_the_option_the_file_or_the_extent, *boost::unit_test::tolerance(1e-15)) {
    io::PackingFile<2> f;
    f.position = {mm::Vec<2>(0.1, 0.2), mm::Vec<2>(0.5, 0.3)};
    f.radius = {0.05, 0.1};
    // The particles' extent, no periodic axis.
    auto d = io::packing_domain<2>(f, {}, "");
    BOOST_TEST(d.lo()[0] == 0.05);
    BOOST_TEST(d.hi()[0] == 0.6);
    BOOST_TEST(d.lo()[1] == 0.15);
    BOOST_TEST(d.hi()[1] == 0.4);
    BOOST_TEST(!d.any_periodic());
    // A periodic axis needs bounds that the extent cannot give.
    BOOST_TEST(message_of([&] { io::packing_domain<2>(f, {}, "x"); }) ==
               "periodic axis x needs the box's bounds, and the file gives none: give them (--box in the programs)");
    // The option's box and axes.
    d = io::packing_domain<2>(f, {0, 1, -1, 2}, "z");
    BOOST_TEST(d.hi()[0] == 1.0);
    BOOST_TEST(d.lo()[1] == -1.0);
    BOOST_TEST((!d.periodic(0) && d.periodic(1)));
    BOOST_TEST(message_of([&] { io::packing_domain<2>(f, {0, 1, 0}, ""); }) == "a 2D box needs 4 numbers (lo hi per axis), got 3");
    BOOST_TEST(message_of([&] { io::packing_domain<2>(f, {0, 1, 2, 1}, ""); }).find("a box needs finite bounds with hi > lo") !=
               std::string::npos);
    // A dump's own box and pp axes, unless the options say otherwise.
    f.box = std::pair{mm::Vec<2>(0, 0), mm::Vec<2>(0.7, 0.8)};
    f.periodic = {true, false};
    d = io::packing_domain<2>(f, {}, "");
    BOOST_TEST(d.hi()[1] == 0.8);
    BOOST_TEST((d.periodic(0) && !d.periodic(1)));
    d = io::packing_domain<2>(f, {}, "z");
    BOOST_TEST((!d.periodic(0) && d.periodic(1)));
}

template <int dim>
void round_trip() {
    std::vector<mm::Vec<dim>> x(3);
    const std::vector<double> r{1e-3 / 3.0, 0.7e-3, 1.1e-3 + 1e-19};
    for (std::size_t p = 0; p < x.size(); ++p)
        for (int a = 0; a < dim; ++a) x[p][a] = 0.1 / 7.0 * double(p + 1) + 1e-3 * std::sqrt(double(a + 2));
    std::array<bool, dim> periodic{};
    periodic[0] = true;  // one periodic axis, the others bounded: both flags written
    const mm::Domain<dim> box(mm::Vec<dim>::Constant(-0.01 / 3.0), mm::Vec<dim>::Constant(0.2 + 1.0 / 3.0), periodic);
    const fs::path path = fs::temp_directory_path() / "micromacro_packing_input_test" / ("written" + std::to_string(dim) + ".dump");
    fs::create_directories(path.parent_path());
    io::write_lammps_dump<dim>(path, x, r, box);
    BOOST_TEST(!fs::exists(path.string() + ".partial"));
    BOOST_TEST((io::guess_format(path.string()) == io::PackingFormat::lammps_dump));
    BOOST_TEST(io::guess_dimension(path.string(), io::PackingFormat::lammps_dump) == dim);  // 2D written without z
    const auto f = io::read_packing<dim>(path.string(), io::PackingFormat::lammps_dump);
    BOOST_TEST_REQUIRE(f.position.size() == x.size());
    for (std::size_t p = 0; p < x.size(); ++p) {
        BOOST_TEST(f.radius[p] == r[p]);
        for (int a = 0; a < dim; ++a) BOOST_TEST(f.position[p][a] == x[p][a]);
    }
    const mm::Domain<dim> read = io::packing_domain<dim>(f, {}, "");
    for (int a = 0; a < dim; ++a) {
        BOOST_TEST(read.lo()[a] == box.lo()[a]);
        BOOST_TEST(read.hi()[a] == box.hi()[a]);
        BOOST_TEST(read.periodic(a) == periodic[a]);
    }
    BOOST_CHECK_THROW(io::write_lammps_dump<dim>(path, x, std::vector<double>(2, 1e-3), box), mm::InputError);
    BOOST_CHECK_THROW(io::write_lammps_dump<dim>("/nonexistent_micromacro_folder/p.dump", x, r, box), mm::InputError);
}

BOOST_AUTO_TEST_CASE(a_written_dump_reads_back_to_the_last_digit_2d) { round_trip<2>(); }
BOOST_AUTO_TEST_CASE(a_written_dump_reads_back_to_the_last_digit_3d) { round_trip<3>(); }

BOOST_AUTO_TEST_SUITE_END()
