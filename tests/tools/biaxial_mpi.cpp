// The biaxial program over MPI ranks (biaxial_mpi under mpirun), against the serial program on
// the same prepared packing: the particles and walls keep the serial bits over the whole run
// without fused multiply-adds (each rank sums in the serial order), so the walls' columns are the
// serial ones and the averages, sums over the ranks, agree to round-off in every row; with fused
// multiply-adds round-off is promised, which chaos would amplify (rows 0-5 compared there;
// docs/mpi.md); the whole run keeps the physics (the side walls hold p); its VTK frames are
// pieces that a .pvtp summary joins; a run killed on two ranks resumes on three, or serially,
// from its checkpoint, and the rows written before the kill are those of an uninterrupted run.
// In 2D and 3D.
#define BOOST_TEST_MODULE tools_biaxial_mpi
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <micromacro/io/state.hpp>

#include "biaxial/timeseries.hpp"
#include "support/programs.hpp"

namespace fs = std::filesystem;

namespace {
const mmtest::WorkFolder work_folder("micromacro_biaxial_mpi_test");
const fs::path& work = work_folder.path;

mmtest::ProgramResult serial(const std::string& args) { return mmtest::run_program(BIAXIAL, args + " --no-pictures --quiet", work); }
mmtest::ProgramResult ranks(int count, const std::string& args) {
    return mmtest::run_program(std::string(MPIEXEC) + " -np " + std::to_string(count) + " --oversubscribe " + BIAXIAL_MPI,
                               args + " --no-pictures --quiet", work);
}
using Series = std::map<std::string, std::vector<double>>;
Series series(const fs::path& dir) { return biaxial::read_timeseries((dir / "timeseries.csv").string()); }

// The columns compared, each relative to its largest magnitude over the compared rows.
const std::vector<std::string> compared = {"sigma_wall_11", "sigma_11", "sigma_22", "trF", "deviatoric_fabric",
                                           "C_n_1111", "coordination", "g2_size", "kinetic_energy", "elastic_energy",
                                           "dissipated_energy", "work_by_walls"};

double largest_difference(const Series& a, const Series& b, std::size_t rows) {
    double worst = 0.0;
    for (const auto& name : compared) {
        const auto &x = a.at(name), &y = b.at(name);
        double scale = 0.0;
        for (std::size_t r = 0; r < rows; ++r) scale = std::max(scale, std::abs(x.at(r)));
        for (std::size_t r = 0; r < rows; ++r)
            if (scale > 0) worst = std::max(worst, std::abs(x.at(r) - y.at(r)) / scale);
    }
    return worst;
}

// Without fused multiply-adds, where the ranks keep the serial bits: every row of `d` within
// round-off of `s` (the averages are sums over the ranks) and the walls' columns to the bit.
void check_serial_bits([[maybe_unused]] const Series& s, [[maybe_unused]] const Series& d, [[maybe_unused]] const std::string& run) {
#ifndef MICROMACRO_FP_CONTRACT
    const std::size_t rows = std::min(d.at("time").size(), s.at("time").size());
    const double whole = largest_difference(s, d, rows);
    BOOST_TEST(whole < 1e-12, run << ": the " << rows << " rows differ by " << whole);
    for (const std::string wall : {"wall_1_lower", "wall_1_upper", "wall_2_lower", "wall_2_upper"})
        BOOST_TEST((d.at(wall) == s.at(wall)), run << ": " << wall << ", the serial bits");
#endif
}

// A prepared packing of the quick preset with fewer particles, made once per dimension.
fs::path prepared(int dim) {
    const fs::path dir = work / ("prepared" + std::to_string(dim));
    if (!fs::exists(dir / "prepared.state")) {
        const auto r = serial("--dim " + std::to_string(dim) + " --preset quick --particles " + (dim == 2 ? "200" : "250") +
                              " --vtk-every 0 --out " + dir.string());
        if (r.status != 0) throw std::runtime_error("biaxial failed: " + r.err);
    }
    return dir / "prepared.state";
}
}  // namespace

// From one prepared packing, 1, 2 and 3 ranks (3D: 2) against the serial program: the same rows
// to round-off (over the first five output intervals with fused multiply-adds, over the whole run
// without, the walls' columns to the bit), the same number of rows, and the walls at p.
BOOST_AUTO_TEST_CASE(the_ranks_give_the_serial_rows) {
    for (const int dim : {2, 3}) {
        const std::string from = " --dim " + std::to_string(dim) + " --preset quick --period 0.05 --vtk-every 0 --from-prepared " + prepared(dim).string();
        const fs::path reference = work / ("serial" + std::to_string(dim));
        BOOST_TEST_REQUIRE(serial(from + " --out " + reference.string()).status == 0);
        const Series s = series(reference);
        for (const int count : dim == 2 ? std::vector<int>{1, 2, 3} : std::vector<int>{2}) {
            const fs::path dir = work / ("ranks" + std::to_string(dim) + "_" + std::to_string(count));
            const auto r = ranks(count, from + " --out " + dir.string());
            BOOST_TEST_REQUIRE(r.status == 0, r.err);
            const Series d = series(dir);
            BOOST_TEST(d.at("time").size() == s.at("time").size());
            const double difference = largest_difference(s, d, 6);
            BOOST_TEST(difference < 1e-9, dim << "D, " << count << " ranks: rows 0-5 differ by " << difference);
            check_serial_bits(s, d, std::to_string(dim) + "D, " + std::to_string(count) + " ranks");
            // Chaos takes the rows apart later; the controlled side wall holds p at the end either way.
            const double p = dim == 2 ? 20.0 : 1e4;
            BOOST_TEST(std::abs(d.at("sigma_wall_11_upper").back() / p - 1.0) < 0.02);
            const auto run = nlohmann::json::parse(mmtest::slurp(dir / "run.json"));
            BOOST_TEST(run.at("timing").at("ranks").get<int>() == count);
        }
    }
}

// A run from scratch, its preparation over the ranks too: without fused multiply-adds 1 and 2
// ranks give the serial program's walls to the bit and its rows to round-off (the averages are
// sums over the ranks), from the placement through the loading, and as many rows. The phases'
// switches gather the whole scene in the serial numbering (mpi::whole_scene), which the
// preparation's spatial sort made other than the ids' order.
BOOST_AUTO_TEST_CASE(a_run_from_scratch_gives_the_serial_rows) {
    const fs::path reference = prepared(2).parent_path();  // the serial program's whole run
    const Series s = series(reference);
    for (const int count : {1, 2}) {
        const fs::path dir = work / ("scratch_" + std::to_string(count));
        const auto r = ranks(count, "--dim 2 --preset quick --particles 200 --vtk-every 0 --out " + dir.string());
        BOOST_TEST_REQUIRE(r.status == 0, r.err);
        const Series d = series(dir);
        BOOST_TEST_REQUIRE(d.at("time").size() == s.at("time").size());
        // With fused multiply-adds only round-off is promised, and the preparation's stopping rule
        // may then end a step apart: the rows are compared without them only.
        check_serial_bits(s, d, std::to_string(count) + " ranks from scratch");
    }
}

// Killed on two ranks after a checkpoint; resumed on three ranks and, from a copy, by the serial
// program: the rows up to the checkpoint are the uninterrupted two-rank run's bits, the next ones
// agree to round-off, and nothing is left to resume into.
BOOST_AUTO_TEST_CASE(a_checkpoint_resumes_on_another_count_of_ranks) {
    const std::string from = " --preset quick --period 0.05 --from-prepared " + prepared(2).string();
    const fs::path whole = work / "uninterrupted", killed = work / "killed", copy = work / "killed_copy";
    BOOST_TEST_REQUIRE(ranks(2, from + " --vtk-every 0 --out " + whole.string()).status == 0);
    const auto k = ranks(2, from + " --vtk-every 0 --checkpoint-every 0.003 --stop-after-rows 25 --out " + killed.string());
    BOOST_TEST(k.status != 0);
    BOOST_TEST_REQUIRE(fs::exists(killed / "checkpoint.state"));
    const std::size_t saved = nlohmann::json::parse(micromacro::io::state_text(killed / "checkpoint.state", "checkpoint")).at("rows");
    BOOST_TEST_REQUIRE(saved > 6);
    fs::copy(killed, copy, fs::copy_options::recursive);
    const auto three = ranks(3, "--resume " + killed.string());
    BOOST_TEST_REQUIRE(three.status == 0, three.err);
    const auto one = serial("--resume " + copy.string());
    BOOST_TEST_REQUIRE(one.status == 0, one.err);
    BOOST_TEST(!fs::exists(killed / "checkpoint.state"));
    const Series w = series(whole);
    for (const fs::path& dir : {killed, copy}) {
        const Series r = series(dir);
        BOOST_TEST_REQUIRE(r.at("time").size() == w.at("time").size());
        BOOST_TEST(largest_difference(w, r, saved) == 0.0);
        Series after, expected;
        for (const auto& name : compared) {
            const auto first = static_cast<std::ptrdiff_t>(saved);
            after[name] = std::vector<double>(r.at(name).begin() + first, r.at(name).begin() + first + 6);
            expected[name] = std::vector<double>(w.at(name).begin() + first, w.at(name).begin() + first + 6);
        }
        BOOST_TEST(largest_difference(expected, after, 6) < 1e-9, dir.string());
    }
}

#ifdef BIAXIAL_WITH_VTK
// The frames of a run over three ranks: each a .pvtp summary of three pieces in the .pvd series.
BOOST_AUTO_TEST_CASE(the_frames_are_pieces_of_one_data_set) {
    const fs::path dir = work / "frames";
    const auto r = ranks(3, "--preset quick --period 0.05 --vtk-every 20 --from-prepared " + prepared(2).string() + " --out " + dir.string());
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const std::string pvd = mmtest::slurp(dir / "vtk" / "particles.pvd");
    BOOST_TEST(pvd.find("particles_0.pvtp") != std::string::npos);
    for (const std::string frame : {"particles_0", "contacts_0", "particles_3"})
        for (int piece = 0; piece < 3; ++piece) BOOST_TEST(fs::exists(dir / "vtk" / (frame + "_" + std::to_string(piece) + ".vtp")));
    BOOST_TEST(fs::exists(dir / "vtk" / "walls_0.vtp"));
}
#endif
