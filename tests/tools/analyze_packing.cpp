// The packing analyser end to end: the same packing as CSV and as a LAMMPS dump gives identical
// JSON, the JSON carries the exact lattice values, and every bad input gets a message naming the
// file and line with a non-zero exit.
#define BOOST_TEST_MODULE tools_analyze_packing
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/programs.hpp"
#include "support/scenes.hpp"

using namespace mmtest;
namespace fs = std::filesystem;

namespace {
const mmtest::WorkFolder work_folder("micromacro_analyze_packing_test");  // removed when the test process ends
const fs::path& work = work_folder.path;

mmtest::ProgramResult run(const std::string& args) { return mmtest::run_program(ANALYZE_PACKING, args, work); }

std::string write(const std::string& name, const std::string& text) { return mmtest::write_file(work, name, text); }

std::string num(double v) {
    std::ostringstream s;
    s << std::setprecision(17) << v;
    return s.str();
}

// A packing as a CSV file and as a LAMMPS dump with the given periodic box.
template <int dim>
std::pair<std::string, std::string> both_files(const RandomPacking<dim>& p, double L, const std::string& stem) {
    std::ostringstream csv, dump;
    csv << (dim == 2 ? "id,x,z,r\n" : "id,x,y,z,r\n");
    dump << "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n" << p.x.size() << "\nITEM: BOX BOUNDS pp pp pp\n";
    for (int a = 0; a < 3; ++a) dump << "0 " << (a < dim ? num(L) : "1") << "\n";
    dump << "ITEM: ATOMS id type x y z diameter\n";
    for (std::size_t i = 0; i < p.x.size(); ++i) {
        csv << i + 1;
        dump << i + 1 << " 1";
        for (int a = 0; a < dim; ++a) {
            csv << "," << num(p.x[i][a]);
            dump << " " << num(p.x[i][a]);
        }
        if (dim == 2) dump << " 0";
        csv << "," << num(p.r[i]) << "\n";
        dump << " " << num(2 * p.r[i]) << "\n";
    }
    return {write(stem + ".csv", csv.str()), write(stem + ".dump", dump.str())};
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(csv_and_lammps_agree, D, Dims) {
    constexpr int dim = D::value;
    const double L = dim == 2 ? 0.03 : 0.01;
    // Diameters exactly twice radii in binary: radii that are multiples of 2^-20 m.
    auto p = random_packing<dim>(300, 0.5e-3, 1.5e-3, L, 21, true, true);
    for (auto& r : p.r) r = std::ldexp(std::round(std::ldexp(r, 20)), -20);
    const auto [csv, dump] = both_files<dim>(p, L, "packing" + std::to_string(dim));
    std::string box;
    for (int a = 0; a < dim; ++a) box += " 0 " + num(L);
    const std::string axes = dim == 2 ? "x,z" : "x,y,z";
    for (std::string rule : {"contact", "center"}) {
        const std::string common = " --k 1e5 --kt 2e4 --rule " + rule;
        const auto from_csv = run(csv + " --box" + box + " --periodic " + axes + common);
        const auto from_dump = run(dump + " --dim " + std::to_string(dim) + common);
        BOOST_TEST_REQUIRE(from_csv.status == 0, from_csv.err);
        BOOST_TEST_REQUIRE(from_dump.status == 0, from_dump.err);
        BOOST_TEST(from_csv.out == from_dump.out);
        // And the same numbers as the library in-process.
        mm::PackingSnapshot<dim> s;
        s.domain = periodic_box<dim>(L);
        s.position = p.x;
        s.radius = p.r;
        mm::detect_contacts(s, 1e5, 2e4);
        mm::AveragingOptions o;
        o.rule = rule == "contact" ? mm::SelectionRule::contact_point : mm::SelectionRule::particle_centre;
        const auto m = mm::average(s, mm::Region<dim>::whole(s), o);
        const nlohmann::json j = nlohmann::json::parse(from_csv.out);
        BOOST_TEST(j["dim"] == dim);
        BOOST_TEST(j["contacts"].get<std::size_t>() == m.contacts);
        BOOST_TEST(j["stress"][0][0].get<double>() == m.stress(0, 0));
        BOOST_TEST(j["stiffness_normal"][0][0][1][1].get<double>() == m.stiffness_normal(0, 0, 1, 1));
        BOOST_TEST(j["stiffness_tangential"][0][1][0][1].get<double>() == m.stiffness_tangential(0, 1, 0, 1));
        BOOST_TEST(j["g2"].get<double>() == m.g2);
    }
}

// The triangular lattice through the file route: C_1111 = 3 sqrt(3)/4 k, C_1122 = sqrt(3)/4 k.
BOOST_AUTO_TEST_CASE(lattice_values_in_json) {
    const double l = 2e-3, h = std::sqrt(3.0) * l, k_file = 1e5;
    std::ostringstream csv;
    csv << "x,z,r\n";
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 3; ++j) {
            csv << num(i * l) << "," << num(j * h) << "," << num(0.5 * l * (1 + 1e-13)) << "\n";
            csv << num((i + 0.5) * l) << "," << num((j + 0.5) * h) << "," << num(0.5 * l * (1 + 1e-13)) << "\n";
        }
    const auto file = write("triangular.csv", csv.str());
    const auto r = run(file + " --box 0 " + num(6 * l) + " 0 " + num(3 * h) + " --periodic x,z");
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    BOOST_TEST(std::abs(j["stiffness_normal"][0][0][0][0].get<double>() / (3 * std::sqrt(3.0) / 4 * k_file) - 1) < 1e-10);
    BOOST_TEST(std::abs(j["stiffness_normal"][0][0][1][1].get<double>() / (std::sqrt(3.0) / 4 * k_file) - 1) < 1e-10);
    BOOST_TEST(std::abs(j["coordination"].get<double>() - 6.0) < 1e-15);
    BOOST_TEST(std::abs(j["coordination_without_rattlers"].get<double>() - 6.0) < 1e-15);  // no rattlers in a lattice
    BOOST_TEST(std::abs(j["contact_number_density"].get<double>() - 6 * j["volume_fraction"].get<double>()) < 1e-10);
}

// Tangential forces from a contact-force file enter the tangential stress: on a square lattice a
// force t on i from j (j = i + 1 along x) adds l t to sigma_12 per contact.
BOOST_AUTO_TEST_CASE(contact_force_file) {
    const double l = 2e-3;
    std::ostringstream csv, forces;
    csv << "id,x,z,r\n";
    int id = 100;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) csv << id++ << "," << num((i + 0.5) * l) << "," << num((j + 0.5) * l) << "," << num(0.5 * l * (1 + 1e-9)) << "\n";
    forces << "i,j,ft_x,ft_z\n";
    forces << "100,101,0.01,-0.25\n";  // on 100 from its right neighbour 101 (the normal part is dropped)
    const auto packing = write("square.csv", csv.str()), force_file = write("forces.csv", forces.str());
    const std::string box = " --box 0 " + num(4 * l) + " 0 " + num(4 * l) + " --periodic x,z";
    const auto r = run(packing + box + " --contact-forces " + force_file);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    // Contact (100, 101): branch r_100 - r_101 = -l e_x, force on 100 = -0.25 e_z:
    // sigma_xz = (-l)(-0.25) / V.
    const double V = 16 * l * l;
    BOOST_TEST(std::abs(j["stress_tangential"][0][1].get<double>() - l * 0.25 / V) < 1e-12 * l * 0.25 / V);
    BOOST_TEST(std::abs(j["stress_tangential"][1][0].get<double>()) < 1e-20);
    // Every branch has one length here, so the anisotropy's stress-force-fabric relation rebuilds
    // the deviatoric stress over p exactly (the symmetric part: the tangential force makes sigma_xz
    // differ from sigma_zx).
    const auto& an = j["anisotropy"];
    const double p = 0.5 * (j["stress"][0][0].get<double>() + j["stress"][1][1].get<double>());
    const double s_xz = 0.5 * (j["stress"][0][1].get<double>() + j["stress"][1][0].get<double>());
    BOOST_TEST(std::abs(an["stress_ratio"][0][1].get<double>() - s_xz / p) < 1e-12 * std::abs(s_xz / p));
    BOOST_TEST(std::abs(an["stress_ratio"][0][0].get<double>() - (j["stress"][0][0].get<double>() - p) / p) < 1e-12);
    BOOST_TEST(an["a_t"].get<double>() > 0.0);

    const auto apart = write("apart.csv", "i,j,ft_x,ft_z\n100,110,0,1\n");
    const auto bad = run(packing + box + " --contact-forces " + apart);
    BOOST_TEST(bad.status != 0);
    BOOST_TEST(bad.err.find("apart.csv:2: particles 100 and 110 do not overlap") != std::string::npos, bad.err);
    const auto twice = write("twice.csv", "i,j,ft_x,ft_z\n100,101,0,1\n101,100,0,2\n");  // one contact, two forces
    const auto repeated = run(packing + box + " --contact-forces " + twice);
    BOOST_TEST(repeated.exit_code() == 1);
    BOOST_TEST(repeated.err.find("twice.csv:3: lists the contact of particles 101 and 100 again (first on line 2)") != std::string::npos,
               repeated.err);
    const auto unknown = write("unknown.csv", "i,j,ft_x,ft_z\n100,7,0,1\n");
    BOOST_TEST(run(packing + box + " --contact-forces " + unknown).err.find("unknown.csv:2: particle id 7 is not in the packing") !=
               std::string::npos);
}

BOOST_AUTO_TEST_CASE(bad_inputs_name_file_and_line) {
    struct Case {
        std::string name, text, args, expect;
    };
    const Case cases[] = {
        {"missing.csv", "x,r\n0,1\n", "", "missing.csv:1: missing column 'z'"},
        {"text.csv", "x,z,r\n0,0,1e-3\n0.1,abc,1e-3\n", "", "text.csv:3: column 'z': 'abc' is not a finite number"},
        {"negative.csv", "x,z,r\n0,0,1e-3\n# comment\n0.1,0,-1e-3\n", "", "negative.csv:4: radius -1e-3 is not positive"},
        {"empty.csv", "", "", "empty.csv: the file is empty"},
        {"header_only.csv", "x,z,r\n", "", "header_only.csv: the file holds no particles"},
        {"same.csv", "x,z,r\n0,0,1e-3\n1,1,1e-3\n0,0,2e-3\n", "", "same.csv:4: particle has the same centre as the particle on line 2"},
        {"short.csv", "x,z,r\n0,0\n", "", "short.csv:2: has 2 fields, the header has 3"},
        {"count.dump", "ITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\nITEM: ATOMS id x y z radius\n1 0.5 0.5 0.5 0.1\n",
         "", "count.dump:8: ITEM: NUMBER OF ATOMS says 2, the file holds 1"},
        {"noatoms.dump", "ITEM: TIMESTEP\n0\n", "--format lammps", "noatoms.dump:2: no ITEM: ATOMS section"},
        {"ok.csv", "x,z,r\n0,0,1e-3\n", "--rule nearest", "--rule 'nearest' is unknown"},
        {"ok2.csv", "x,z,r\n0,0,1e-3\n2e-3,0,1e-3\n", "--periodic q --box 0 1 0 1", "periodic axes 'q': unknown axis 'q'; in 2D name them from x, z"},
        // A 3D file read as 2D, in either format: refused, not read without y.
        {"three.csv", "x,y,z,r\n0,0,0,1e-3\n1.9e-3,0,0,1e-3\n0,1.9e-3,0,1e-3\n", "--dim 2",
         "three.csv:1: the header names a y column: a 3D packing, read as 2D"},
        {"three.dump", "ITEM: ATOMS id x y z radius\n1 0 0 0 1e-3\n2 0 0 1.9e-3 1e-3\n", "--dim 2",
         "three.dump:3: z = 1.9e-3 differs from the first atom's"},
        {"semicolons.csv", "x;z;r\n0;0;1e-3\n", "", "semicolons.csv:1: the header is separated by ';', not commas"},
        {"tabs.csv", "x\tz\tr\n0\t0\t1e-3\n", "", "tabs.csv:1: the header is separated by tabs"},
        // Results that cannot be: one particle's own extent as the box, and overflow.
        {"one.csv", "x,z,r\n0,0,1e-3\n", "", "one.csv holds one particle; averages need a packing"},
        {"huge.csv", "x,z,r\n0,0,1e300\n1,0,1e300\n", "", "is not finite: the file's values overflow"},
        {"huge_id.csv", "id,x,z,r\n1e300,0,0,1e-3\n", "", "huge_id.csv:2: column 'id': '1e300' is not a whole number"},
        // Ambiguous files: which column or which particle was meant cannot be told.
        {"two_sizes.csv", "x,z,r,diameter\n0,0,1e-3,3e-3\n2e-3,0,1e-3,2e-3\n", "",
         "two_sizes.csv:1: the header has more than one size column ('r', 'diameter'); keep one of them"},
        {"two_x.csv", "x,z,r,x\n0,0,1e-3,5\n2e-3,0,1e-3,6\n", "", "two_x.csv:1: column 'x' is named twice (fields 1 and 4)"},
        {"two_ids.dump", "ITEM: ATOMS id x y z radius\n1 0 0 0 1e-3\n2 2e-3 0 0 1e-3\n1 4e-3 0 0 1e-3\n", "--dim 2",
         "two_ids.dump:4: particle id 1 is taken by the particle on line 2 already"},
    };
    for (const auto& c : cases) {
        const auto path = write(c.name, c.text);
        const auto r = run(path + " " + c.args);
        BOOST_TEST(r.exit_code() == 1, c.name << ": exit status " << r.exit_code());
        BOOST_TEST(r.err.find(c.expect) != std::string::npos, c.name << ": stderr was '" << r.err << "'");
        BOOST_TEST(r.out.empty(), c.name << ": no partial output");
    }
    const auto unknown = run(write("ok3.csv", "x,z,r\n0,0,1e-3\n") + " --frobnicate");
    BOOST_TEST(unknown.exit_code() == 1);  // a parse error exits 1, as every other error
    BOOST_TEST(unknown.err.find("frobnicate") != std::string::npos);
    // --output writes the whole file or nothing.
    const auto out = (work / "result.json").string();
    fs::remove(out);
    BOOST_TEST(run(write("ok4.csv", "x,z,r\n0,0,1e-3\n2e-3,0,1e-3\n") + " -o " + out).status == 0);
    BOOST_TEST(nlohmann::json::parse(std::ifstream(out))["particles"].get<int>() >= 0);
    BOOST_TEST(run(write("ok5.csv", "x,z,r\n0,0,1e-3\n") + " -o /nonexistent/dir/result.json").status != 0);
    // The input is never overwritten, and a full standard output is an error, not exit 0.
    const std::string input = write("ok6.csv", "x,z,r\n0,0,1e-3\n2e-3,0,1e-3\n");
    const auto onto = run(input + " -o " + input);
    BOOST_TEST(onto.exit_code() == 1);
    BOOST_TEST(onto.err.find("is the input") != std::string::npos, onto.err);
    BOOST_TEST(mmtest::slurp(input) == "x,z,r\n0,0,1e-3\n2e-3,0,1e-3\n");
    const auto full = mmtest::run_program("sh -c '" + std::string(ANALYZE_PACKING) + " " + input + " > /dev/full'", "", work);
    BOOST_TEST(full.exit_code() == 1);
    BOOST_TEST(full.err.find("cannot write to standard output") != std::string::npos, full.err);
    // A UTF-8 byte-order mark (spreadsheet exports) is not part of the first column's name.
    BOOST_TEST(run(write("bom.csv", "\xef\xbb\xbfx,z,r\n0,0,1e-3\n2e-3,0,1e-3\n")).status == 0);
}
