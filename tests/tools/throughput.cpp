// The throughput benchmark's input side end to end: a packing given as a file (CSV or LAMMPS
// dump) is timed on exactly its own contacts and time step, the JSON line carries the issue's
// keys and the configuration, and bad input is refused with a message and no result line.
// Nothing here asserts a speed.
#define BOOST_TEST_MODULE tools_throughput
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include <micromacro/micromacro.hpp>

#include "support/programs.hpp"

namespace fs = std::filesystem;
namespace mm = micromacro;

namespace {
const mmtest::WorkFolder work_folder("micromacro_throughput_test");  // removed when the test process ends
const fs::path& work = work_folder.path;

mmtest::ProgramResult run(const std::string& args) { return mmtest::run_program(THROUGHPUT, args, work); }

nlohmann::json run_json(const std::string& args) {
    const auto r = run(args + " --json");
    BOOST_TEST_REQUIRE(r.status == 0, args << ": stderr was '" << r.err << "'");
    return nlohmann::json::parse(r.out);
}

std::string num(double v) {
    std::ostringstream s;
    s << std::setprecision(17) << v;
    return s.str();
}

// A simple square (2D) or cubic (3D) lattice, `side` particles per axis, spacing 2a, pressed
// together by 1e-4 of a diameter: in the periodic box of side `side` x 2a every particle touches
// exactly its 2 dim lattice neighbours, so the packing has dim N contacts.
struct Lattice {
    int dim, side;
    double a;  // radius without the overlap
    double box() const { return side * 2.0 * a; }
    std::size_t particles() const { return static_cast<std::size_t>(std::pow(side, dim)); }
    double radius() const { return a * 1.0001; }

    std::string csv(const std::string& name) const {
        std::ostringstream out;
        out << (dim == 2 ? "x,z,r\n" : "x,y,z,r\n");
        for (std::size_t p = 0; p < particles(); ++p) {
            for (int k = 0, t = static_cast<int>(p); k < dim; ++k, t /= side) out << num((t % side + 0.5) * 2.0 * a) << ",";
            out << num(radius()) << "\n";
        }
        return write(name, out.str());
    }
    std::string dump(const std::string& name) const {  // 3D, periodic on every axis
        std::ostringstream out;
        out << "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n" << particles() << "\nITEM: BOX BOUNDS pp pp pp\n";
        for (int k = 0; k < 3; ++k) out << "0 " << num(box()) << "\n";
        out << "ITEM: ATOMS id type x y z diameter\n";
        for (std::size_t p = 0; p < particles(); ++p) {
            out << p + 1 << " 1";
            for (int k = 0, t = static_cast<int>(p); k < 3; ++k, t /= side) out << " " << num((t % side + 0.5) * 2.0 * a);
            out << " " << num(2.0 * radius()) << "\n";
        }
        return write(name, out.str());
    }
    std::string box_option() const {
        std::string s = " --box";
        for (int k = 0; k < dim; ++k) s += " 0 " + num(box());
        return s;
    }
    static std::string write(const std::string& name, const std::string& text) { return mmtest::write_file(work, name, text); }
};

// t_c of two particles of radius a (Eq. 22), as the program computes it.
double contact_duration(double k, double gamma_n, double density, double a) {
    return mm::contact_duration(k, gamma_n, 0.5 * mm::sphere_mass(density, a));
}
}  // namespace

BOOST_AUTO_TEST_CASE(json_line_carries_the_keys_and_the_configuration) {
    const auto j = run_json("--dim 3 --particles 27 --steps 3");
    for (const char* key : {"name", "dim", "particles", "contacts", "steps", "seconds", "particle_steps_per_second",
                            "bytes_per_particle", "threads", "precision", "law", "k", "kt", "mu", "gamma_n", "gamma_t",
                            "density", "contact_duration", "dt", "skin", "energy_books", "periodic", "order", "fma"})
        BOOST_TEST(j.contains(key), key);
#if defined(MICROMACRO_FP_CONTRACT) && defined(__FP_FAST_FMA)
    BOOST_TEST(j["fma"].get<bool>());  // the benchmark was built like this test
#else
    BOOST_TEST(!j["fma"].get<bool>());
#endif
    BOOST_TEST(j["particles"].get<int>() == 27);
    BOOST_TEST(j["contacts"].get<int>() == 81);  // a periodic 3 x 3 x 3 cubic lattice: 3 contacts per particle
    BOOST_TEST(j["periodic"].get<std::string>() == "xyz");
    BOOST_TEST(j["dt"].get<double>() == j["contact_duration"].get<double>() / 50, boost::test_tools::tolerance(1e-5));
    BOOST_TEST(run_json("--dim 2 --particles 16 --steps 3")["contacts"].get<int>() == 32);
}

// A packing of another size than the generated lattice's 1 mm: its own masses set t_c (the
// program used to take a 1 mm particle's mass whatever the file held, and refused 0.1 mm
// particles as unstable).
BOOST_AUTO_TEST_CASE(a_packing_file_is_timed_on_its_own_contacts_and_time_step) {
    for (int dim : {2, 3}) {
        const Lattice lattice{dim, 4, 5e-5};  // 0.1 mm particles
        const std::string file = lattice.csv("lattice" + std::to_string(dim) + ".csv");
        const double gamma_n = 0.004;  // the paper's 0.1 kg/s would overdamp these light particles
        const auto j = run_json("--packing " + file + lattice.box_option() + (dim == 2 ? " --periodic x,z" : " --periodic x,y,z") +
                                " --gamma-n " + num(gamma_n) + " --steps 5");
        BOOST_TEST(j["dim"].get<int>() == dim);  // from the CSV's columns
        BOOST_TEST(j["particles"].get<std::size_t>() == lattice.particles());
        BOOST_TEST(j["contacts"].get<std::size_t>() == dim * lattice.particles());
        const double tc = contact_duration(1e5, gamma_n, 2000, lattice.radius());
        BOOST_TEST(j["contact_duration"].get<double>() == tc, boost::test_tools::tolerance(1e-5));
        BOOST_TEST(j["dt"].get<double>() == tc / 50, boost::test_tools::tolerance(1e-5));
        BOOST_TEST(j["skin"].get<double>() == 0.2 * lattice.radius(), boost::test_tools::tolerance(1e-5));
        BOOST_TEST(j["packing"].get<std::string>() == file);
        // --dt, --density and --skin are taken as given.
        const auto k = run_json("--packing " + file + lattice.box_option() + (dim == 2 ? " --periodic xz" : " --periodic xyz") +
                                " --gamma-n 0.004 --density 3000 --dt 1e-9 --skin 2e-5 --steps 5");
        BOOST_TEST(k["dt"].get<double>() == 1e-9, boost::test_tools::tolerance(1e-5));
        BOOST_TEST(k["skin"].get<double>() == 2e-5, boost::test_tools::tolerance(1e-5));
        BOOST_TEST(k["contact_duration"].get<double>() == contact_duration(1e5, 0.004, 3000, lattice.radius()),
                   boost::test_tools::tolerance(1e-5));
        // Without periodic axes the box is the particles' extent, and the lattice loses its
        // wrap-around contacts: dim side^(dim-1) (side - 1) remain.
        const auto open = run_json("--packing " + file + " --gamma-n 0.004 --steps 5");
        BOOST_TEST(open["periodic"].get<std::string>() == "");
        BOOST_TEST(open["contacts"].get<std::size_t>() == dim * std::pow(4, dim - 1) * 3);
    }
}

BOOST_AUTO_TEST_CASE(a_lammps_dump_gives_box_and_periodic_axes_and_agrees_with_the_csv) {
    const Lattice lattice{3, 5, 1e-3};
    const auto dump = run_json("--packing " + lattice.dump("lattice.dump") + " --steps 5");
    const auto csv = run_json("--packing " + lattice.csv("lattice.csv") + lattice.box_option() + " --periodic x,y,z --steps 5");
    BOOST_TEST(dump["dim"].get<int>() == 3);
    BOOST_TEST(dump["periodic"].get<std::string>() == "xyz");  // the dump's pp axes
    BOOST_TEST(dump["contacts"].get<std::size_t>() == 3 * lattice.particles());
    for (const char* key : {"particles", "contacts", "periodic", "dt", "skin"}) BOOST_TEST(dump[key] == csv[key], key);
}

// --write-packing: the generated lattice, written as a dump (2D without a z column) and timed
// from the file, is the same scene: dimension, periodic axes, contacts and time step.
BOOST_AUTO_TEST_CASE(a_written_packing_times_as_the_generated_one) {
    for (int dim : {2, 3}) {
        const std::string file = (work / ("written" + std::to_string(dim) + ".dump")).string();
        const std::string lattice = "--dim " + std::to_string(dim) + " --particles " + (dim == 2 ? "36" : "64") + " --steps 3";
        const auto made = run_json(lattice + " --write-packing " + file);
        const auto read = run_json("--packing " + file + " --steps 3");
        for (const char* key : {"dim", "particles", "contacts", "dt", "contact_duration", "skin", "periodic"})
            BOOST_TEST(made[key] == read[key], key);
        const auto again = run(lattice + " --write-packing " + file);  // an existing file is not replaced
        BOOST_TEST(again.exit_code() == 1);
        BOOST_TEST(again.err.find("--write-packing") != std::string::npos, again.err);
    }
}

// The JSON line stays JSON whatever the file is called.
BOOST_AUTO_TEST_CASE(file_names_are_escaped_in_the_json_line) {
    const Lattice lattice{2, 3, 1e-3};
    const std::string file = lattice.csv("odd \"name\" \\ here.csv");
    const auto j = run_json("--packing '" + file + "'" + lattice.box_option() + " --periodic x,z --steps 2");
    BOOST_TEST(j["packing"].get<std::string>() == file);
}

BOOST_AUTO_TEST_CASE(bad_input_is_refused_with_a_message_and_no_result) {
    const Lattice lattice{3, 4, 5e-5};
    const std::string file = lattice.csv("bad_inputs.csv");
    struct Case {
        std::string args, expect;
    };
    const Case cases[] = {
        {"--packing " + file + lattice.box_option() + " --periodic x,q --gamma-n 0.004", "unknown axis 'q'"},
        {"--packing " + file + " --box 0 1 0 1 --gamma-n 0.004", "a 3D box needs 6 numbers (lo hi per axis), got 4"},
        {"--packing " + file + " --gamma-n 0.004 --dt 1e-6", "time step dt = 1e-06 s (--dt) exceeds the stability limit"},
        {"--packing " + file, "the contact is overdamped"},  // 0.1 kg/s on 0.1 mm particles
        {"--packing " + file + " --particles 100", "--particles excludes --packing"},
        {"--box 0 1 0 1", "--box requires --packing"},
        {"--particles 3", "--particles 3 is too few: the periodic box needs a full lattice at least 3 particles wide, 9 in 2D"},
        {"--particles 5", "--particles 5 is too few: the periodic box needs a full lattice at least 3 particles wide, 9 in 2D"},
        {"--dim 3 --particles 20", "--particles 20 is too few: the periodic box needs a full lattice at least 3 particles wide, 27 in 3D"},
        {"--steps 0", "--steps: Value 0 not in range"},
        {"--dt-fraction 50 --dt 1e-7", "excludes"},
        {"--law elastic", "--law"},
        // Values that overflow the derived quantities: the option at fault is named, not the library's call.
        {"--k 1e308", "--k 1e+308 N/m with --density 2000 kg/m^3 gives a contact duration"},
        {"--density 1e308", "--density 1e+308 kg/m^3 gives a particle of the mean radius"},
        {"--kt 1e308", "exceeds the stability limit 0 s of the lightest particles' contact (set by --k, --kt"},
    };
    for (const auto& c : cases) {
        const auto r = run(c.args + " --json");
        BOOST_TEST(r.exit_code() == 1, c.args << ": exit status " << r.exit_code());
        BOOST_TEST(r.err.find(c.expect) != std::string::npos, c.args << ": stderr was '" << r.err << "'");
        BOOST_TEST(r.out.empty(), c.args << ": no result line");
    }
}
