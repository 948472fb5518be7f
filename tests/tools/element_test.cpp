// The element_test program end to end, on small packings: each preset follows its path (the
// servo-held stresses within a few per cent of their targets at the default inertial number
// 1e-3, the strain-controlled ones exact), the probes agree with the averaged stiffness where
// they must, a killed run resumes bit for bit, a packing file is read, and bad input is refused
// before anything is written.
#define BOOST_TEST_MODULE tools_element_test
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "biaxial/timeseries.hpp"
#include "support/programs.hpp"

namespace fs = std::filesystem;

namespace {
const mmtest::WorkFolder work_folder("micromacro_element_test");  // removed when the test process ends
const fs::path& work = work_folder.path;

mmtest::ProgramResult run(const std::string& args) { return mmtest::run_program(ELEMENT_TEST, args + " --quiet --no-pictures", work); }

/// A 2D packing of 150 disks prepared once (p = 1000 N/m) that the 2D cases load.
const fs::path& prepared_2d() {
    static const fs::path state = [] {
        const auto r = run("--preset shear-p --particles 150 --strain 0.01 --rows 2 --vtk-every-rows 0 --out " + (work / "prep2d").string());
        BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
        return work / "prep2d" / "prepared.state";
    }();
    return state;
}

/// A prepared.state of the biaxial program (80 disks, a short loading), which element_test refuses.
fs::path biaxial_prepared() {
    const auto dir = work / "biaxial";
    const auto r = mmtest::run_program(BIAXIAL, "--preset quick --particles 80 --period 0.02 --relax 0.002 --quiet --no-pictures --out " +
                                                    dir.string(), work);
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    return dir / "prepared.state";
}

std::map<std::string, std::vector<double>> series(const fs::path& dir) { return biaxial::read_timeseries((dir / "timeseries.csv").string()); }

/// The largest |column / value - 1| over the rows after the first.
double largest_deviation(const std::vector<double>& column, double value) {
    double worst = 0.0;
    for (std::size_t r = 1; r < column.size(); ++r) worst = std::max(worst, std::abs(column[r] / value - 1.0));
    return worst;
}

std::string rows_of(const fs::path& csv) {  // without the first line, the run id
    const std::string text = mmtest::slurp(csv);
    return text.substr(text.find('\n') + 1);
}
}  // namespace

// The preparation ends at rest at p: pressure within 1e-3, no shear stress; simple shear at
// constant p holds sigma_zz, keeps the cell's length along x, and mobilises friction.
BOOST_AUTO_TEST_CASE(simple_shear_at_constant_pressure_2d) {
    const auto dir = work / "shear_p";
    const auto r = run("--preset shear-p --from-prepared " + prepared_2d().string() + " --strain 0.3 --rows 15 --out " + dir.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    const auto s = series(dir);
    BOOST_TEST(std::abs(s.at("pressure")[0] / 1000 - 1) < 1e-3);
    BOOST_TEST(std::abs(s.at("sigma_12")[0]) < 1.0);
    BOOST_TEST(largest_deviation(s.at("sigma_22"), 1000) < 0.02);
    BOOST_TEST(std::abs(s.at("gamma_12").back() - 0.3) < 0.3 / 15);  // to the row
    for (const double e11 : s.at("strain_11")) BOOST_TEST(e11 == 0.0);  // held exactly
    BOOST_TEST(s.at("shear_stress_ratio").back() > 0.15);              // frictional disks, mu = 0.5: 0.2-0.5
    BOOST_TEST(s.at("shear_stress_ratio").back() < 0.7);
    BOOST_TEST(s.at("work_by_cell").back() > 0.0);
    BOOST_TEST(s.at("inertial_number")[5] > 0.5e-3);
    BOOST_TEST(s.at("inertial_number")[5] < 2e-3);
    const auto j = nlohmann::json::parse(mmtest::slurp(dir / "run.json"));
    BOOST_TEST(j.at("program") == "element_test");
    BOOST_TEST(j.at("parameters").at("preset") == "shear-p");
#ifdef ELEMENT_TEST_WITH_VTK
    for (const char* file : {"particles.pvd", "contacts.pvd", "cell.pvd", "cell_0.vtp"}) BOOST_TEST(fs::exists(dir / "vtk" / file), file);
#endif
}

// --help names every preset and says what it does.
BOOST_AUTO_TEST_CASE(help_lists_every_preset) {
    const auto help = mmtest::run_program(ELEMENT_TEST, "--help", work);
    BOOST_TEST(help.exit_code() == 0);
    for (const char* preset : {"isotropic:", "oedometric:", "triaxial:", "shear-p:", "shear-v:", "probes:"})
        BOOST_TEST(help.out.find(preset) != std::string::npos, preset);
    for (const char* option : {"--inertial-number", "--pressure", "--strain", "--from-prepared", "--packing", "--resume"})
        BOOST_TEST(help.out.find(option) != std::string::npos, option);
}

// With VTK and Xvfb, a run ends with its plots and snapshots.
BOOST_AUTO_TEST_CASE(a_run_makes_its_pictures) {
#ifdef ELEMENT_TEST_WITH_VTK
    if (!mmtest::installed("xvfb-run")) return;
    const auto dir = work / "pictures";
    const auto r = mmtest::run_program(ELEMENT_TEST, "--quiet --preset shear-v --from-prepared " + prepared_2d().string() +
                                                         " --strain 0.02 --rows 4 --out " + dir.string(), work);
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    for (const char* file : {"plots/stress.png", "plots/stress_ratio.png", "plots/fabric.png", "snapshots/snapshot_0.png"})
        BOOST_TEST(fs::exists(dir / file), file);
#endif
}

// Constant volume: every length held, so the volume fraction is the prepared one on every row.
BOOST_AUTO_TEST_CASE(simple_shear_at_constant_volume_2d) {
    const auto dir = work / "shear_v";
    const auto r = run("--preset shear-v --from-prepared " + prepared_2d().string() + " --strain 0.1 --rows 5 --out " + dir.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    const auto s = series(dir);
    for (const double v : s.at("volumetric_strain")) BOOST_TEST(std::abs(v) < 1e-12);
    BOOST_TEST(s.at("volume_fraction").back() == s.at("volume_fraction").front(), boost::test_tools::tolerance(1e-12));
}

// Oedometric: only the last axis moves; the lateral stress rises with the axial one (K0 < 1).
BOOST_AUTO_TEST_CASE(oedometric_and_isotropic_2d) {
    const auto oedo = work / "oedometric";
    auto r = run("--preset oedometric --from-prepared " + prepared_2d().string() + " --strain 0.01 --rows 5 --out " + oedo.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    auto s = series(oedo);
    for (const double e11 : s.at("strain_11")) BOOST_TEST(e11 == 0.0);
    BOOST_TEST(s.at("volumetric_strain").back() == s.at("strain_22").back(), boost::test_tools::tolerance(1e-9));
    const double K0 = (s.at("sigma_11").back() - 1000) / (s.at("sigma_22").back() - 1000);
    BOOST_TEST(K0 > 0.2);
    BOOST_TEST(K0 < 1.0);
    // Isotropic to 2 p: it ends at rest at the target.
    const auto iso = work / "isotropic";
    r = run("--preset isotropic --from-prepared " + prepared_2d().string() + " --target-pressure 2000 --strain 0.05 --rows 20 --out " +
            iso.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    s = series(iso);
    BOOST_TEST(std::abs(s.at("pressure").back() / 2000 - 1) < 1e-3);
    BOOST_TEST(s.at("coordination").back() > s.at("coordination").front());
    BOOST_TEST(s.at("volume_fraction").back() > s.at("volume_fraction").front());
}

// Probes: the cell-driven probe and the affinely mapped relaxed one end in the same cell and
// agree; the frozen affine probe is Eq. 9's C : eps up to the geometric terms (p/k = 1e-2);
// relaxation only softens.
BOOST_AUTO_TEST_CASE(probes_against_the_averaged_stiffness_2d) {
    const auto dir = work / "probes";
    const auto r = run("--preset probes --from-prepared " + prepared_2d().string() + " --out " + dir.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    std::ifstream in(dir / "probes.csv");
    std::vector<std::string> names;
    std::size_t directions = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> fields;
        std::stringstream split(line);
        for (std::string f; std::getline(split, f, ',');) fields.push_back(f);
        if (names.empty()) {
            names = fields;
            continue;
        }
        BOOST_REQUIRE(fields.size() == names.size());
        std::map<std::string, double> v;
        for (std::size_t i = 1; i < fields.size(); ++i) v[names[i]] = std::stod(fields[i]);
        BOOST_TEST_CONTEXT(fields[0]) {
            BOOST_TEST(v.at("modulus_predicted") > 0.0);
            BOOST_TEST(std::abs(v.at("modulus_affine") / v.at("modulus_predicted") - 1) < 0.05);
            BOOST_TEST(std::abs(v.at("modulus_cell") / v.at("modulus_relaxed") - 1) < 0.05);
            BOOST_TEST(v.at("modulus_relaxed") < v.at("modulus_affine"));
            BOOST_TEST(v.at("modulus_relaxed") > 0.3 * v.at("modulus_affine"));
        }
        ++directions;
    }
    BOOST_TEST(directions == 5u);
}

// 3D: the triaxial test without walls holds both lateral stresses at p while the axial one
// rises; the axial strain is the imposed one.
BOOST_AUTO_TEST_CASE(triaxial_3d) {
    const auto dir = work / "triaxial3d";
    const auto r = run("--dim 3 --preset triaxial --particles 150 --strain 0.03 --rows 6 --out " + dir.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    const auto s = series(dir);
    BOOST_TEST(std::abs(s.at("pressure")[0] / 5e5 - 1) < 1e-3);
    BOOST_TEST(largest_deviation(s.at("sigma_11"), 5e5) < 0.03);
    BOOST_TEST(largest_deviation(s.at("sigma_22"), 5e5) < 0.03);
    BOOST_TEST(s.at("sigma_33").back() > 1.2 * 5e5);
    BOOST_TEST(std::abs(s.at("strain_33").back() - 0.03) < 0.03 / 6);
    BOOST_TEST(s.count("C_n_3333") == 1u);
    BOOST_TEST(s.count("gamma_13") == 1u);
}

// A packing file (CSV, a square lattice of 64 disks with a box) is prepared to p and sheared.
BOOST_AUTO_TEST_CASE(a_packing_file_is_prepared_and_loaded) {
    std::string csv = "x,z,r\n";
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            csv += std::to_string((i + 0.5) * 2.5e-3) + "," + std::to_string((j + 0.5) * 2.5e-3) + "," + (((i + j) % 2) ? "1e-3" : "0.8e-3") + "\n";
    const auto file = mmtest::write_file(work, "lattice.csv", csv);
    const auto dir = work / "from_file";
    const auto r = run("--preset shear-v --packing " + file + " --box 0 0.02 0 0.02 --strain 0.02 --rows 2 --out " + dir.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    const auto s = series(dir);
    BOOST_TEST(std::abs(s.at("pressure")[0] / 1000 - 1) < 1e-3);
    const auto j = nlohmann::json::parse(mmtest::slurp(dir / "run.json"));
    BOOST_TEST(j.at("plan").at("packing") == file);
}

// Bad input is refused with the option, the value and the fix, and nothing is written.
BOOST_AUTO_TEST_CASE(bad_input_is_refused_before_anything_is_written) {
    const auto out = work / "refused";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"--preset shearing", "--preset 'shearing' is not one of"},
        {"--strain 0", "--strain 0 is out of range"},
        {"--preset triaxial --strain 0.95", "--strain 0.95 is out of range"},
        {"--pressure -1", "--pressure -1 must be a finite number above 0"},
        {"--mu -1", "--mu -1 must be a finite number of 0 or more"},
        {"--gamma-b-prepare 0", "--gamma-b-prepare 0 must be a finite number above 0"},
        {"--from-prepared " + prepared_2d().string() + " --gamma-b-prepare 1", "--gamma-b-prepare made the packing"},
        {"--particles -5", "--particles '-5' is not a whole number"},
        {"--seed 1e19", "--seed '1e19' is not a whole number"},
        {"--target-pressure 10", "--target-pressure 10 must exceed --pressure 1000"},
        {"--from-prepared " + prepared_2d().string() + " --particles 10", "--particles made the packing"},
        {"--from-prepared " + prepared_2d().string() + " --dim 3", "holds a 2D packing; give --dim 2"},
        {"--packing " + (work / "lattice.csv").string() + " --from-prepared " + prepared_2d().string(), "give one"},
        {"--box 0 1 0 1", "--box is the cell of a --packing file"},
        {"--from-prepared " + biaxial_prepared().string(), "is a state of biaxial, not a prepared.state of element_test"},
    };
    for (const auto& [args, message] : cases) {
        BOOST_TEST_CONTEXT(args) {
            fs::remove_all(out);
            const auto r = run(args + " --out " + out.string());
            BOOST_TEST(r.exit_code() == 1);
            BOOST_TEST(r.err.find(message) != std::string::npos, r.err);
            BOOST_TEST(!fs::exists(out));
        }
    }
    // An earlier run in --out is kept unless --overwrite.
    const auto earlier = work / "shear_v";
    if (fs::exists(earlier / "timeseries.csv")) {
        const std::string before = mmtest::slurp(earlier / "timeseries.csv");
        const auto r = run("--from-prepared " + prepared_2d().string() + " --out " + earlier.string());
        BOOST_TEST(r.exit_code() == 1);
        BOOST_TEST(r.err.find("holds an earlier run") != std::string::npos, r.err);
        BOOST_TEST(mmtest::slurp(earlier / "timeseries.csv") == before);
    }
}

// A killed run (--stop-after-rows) resumed from its checkpoint writes the rows the uninterrupted
// run writes, bit for bit.
BOOST_AUTO_TEST_CASE(a_killed_run_resumes_bit_for_bit) {
    const std::string common = "--preset shear-p --from-prepared " + prepared_2d().string() + " --strain 0.1 --rows 10 --checkpoint-every 1e-4";
    const auto whole = work / "whole", killed = work / "killed";
    auto r = run(common + " --out " + whole.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    r = run(common + " --stop-after-rows 6 --out " + killed.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 3, r.err);
    BOOST_TEST(fs::exists(killed / "checkpoint.state"));
    BOOST_TEST(!fs::exists(killed / "timeseries.csv"));
    r = run("--preset triaxial --resume " + killed.string());
    BOOST_TEST(r.exit_code() == 1);
    BOOST_TEST(r.err.find("--preset is a setting of the run --resume continues") != std::string::npos, r.err);
    r = run("--resume " + killed.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    BOOST_TEST(rows_of(killed / "timeseries.csv") == rows_of(whole / "timeseries.csv"));
    BOOST_TEST(!fs::exists(killed / "checkpoint.state"));
}
