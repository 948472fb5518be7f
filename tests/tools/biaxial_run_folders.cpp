// The biaxial program against what a user can do to its run folders and resources: two runs into
// one folder at once, a time series edited before a resume, a full disk, a run larger than the
// machine, and options given with --from-prepared, which act as run.json records them.
#define BOOST_TEST_MODULE tools_biaxial_run_folders
#include <boost/test/unit_test.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/biaxial_runs.hpp"
#include "support/programs.hpp"

namespace fs = std::filesystem;

namespace {
const mmtest::WorkFolder work_folder("micromacro_biaxial_run_folders");  // removed when the test process ends
const fs::path& work = work_folder.path;
constexpr bool with_vtk = mmtest::biaxial_with_vtk;
const std::string small_run = " --preset quick --particles 80 --period 0.02 --relax 0.002 --seed 7 --no-pictures";

mmtest::ProgramResult run(const std::string& args) { return mmtest::run_biaxial(args, work); }
using mmtest::slurp;

nlohmann::json run_json(const fs::path& dir) { return nlohmann::json::parse(slurp(dir / "run.json")); }

/// The first line of a program's standard error.
std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }
}  // namespace

// A folder in use by a running run (its lock held, as a running biaxial holds it) is refused as
// --out and as --resume, and nothing is written into it; once the lock is free the run goes on.
BOOST_AUTO_TEST_CASE(a_folder_in_use_is_refused) {
    const auto dir = work / "in_use";
    fs::create_directories(dir);
    const int fd = ::open((dir / ".lock").c_str(), O_RDWR | O_CREAT, 0644);
    BOOST_TEST_REQUIRE(fd >= 0);
    BOOST_TEST_REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
    const auto second = run(small_run + " --quiet --out " + dir.string());
    BOOST_TEST(second.exit_code() == 1);
    BOOST_TEST(second.err.find("is in use by another biaxial run") != std::string::npos, second.err);
    const auto resumed = run("--quiet --resume " + dir.string());
    BOOST_TEST(resumed.exit_code() == 1);
    BOOST_TEST(resumed.err.find("is in use by another biaxial run") != std::string::npos, resumed.err);
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir)) entries += e.path().filename() != ".lock";
    BOOST_TEST(entries == 0u);
    ::close(fd);  // the run it stood for has ended
    const auto after = run(small_run + " --quiet --out " + dir.string());
    BOOST_TEST(after.exit_code() == 0, after.err);
}

// The audit's two runs into one folder at once: whichever order they meet in, one runs and the
// other is refused (in use, or holding an earlier run), and the folder holds one run whole.
BOOST_AUTO_TEST_CASE(two_runs_into_one_folder_at_once) {
    const auto dir = work / "at_once";
    const std::string first = std::string(BIAXIAL) + small_run + " --quiet --out " + dir.string();
    std::string other_seed = small_run;
    other_seed.replace(other_seed.find("--seed 7"), 8, "--seed 2");
    const std::string second = std::string(BIAXIAL) + other_seed + " --quiet --out " + dir.string();
    const auto both = mmtest::run_program(
        "sh -c '" + first + " > " + (work / "a.txt").string() + " 2>&1 & a=$!; " + second + " > " + (work / "b.txt").string() +
            " 2>&1; b=$?; wait $a; echo $? $b'",
        "", work);
    int a = -1, b = -1;
    std::istringstream(both.out) >> a >> b;
    BOOST_TEST(((a == 0 && b == 1) || (a == 1 && b == 0)), "exit statuses " << a << " and " << b);
    const std::string refused = slurp(work / (a == 1 ? "a.txt" : "b.txt"));
    BOOST_TEST((refused.find("is in use by another biaxial run") != std::string::npos ||
                refused.find("holds an earlier run") != std::string::npos),
               refused);
    const std::string id = run_json(dir)["run_id"];
    BOOST_TEST(slurp(dir / "timeseries.csv").rfind("# run " + id + "\n", 0) == 0u);
    BOOST_TEST(run_json(dir)["parameters"]["seed"].get<int>() == (a == 0 ? 7 : 2));
}

// What a resume continues from is verified like the state files: one digit changed in a row of
// the time series (the same length) is refused, and the restored file resumes.
BOOST_AUTO_TEST_CASE(an_edited_time_series_does_not_resume) {
    const auto dir = work / "edited";
    BOOST_TEST_REQUIRE(run(small_run + " --quiet --checkpoint-every 0.003 --stop-after-rows 25 --out " + dir.string()).exit_code() == 3);
    const fs::path series = dir / "timeseries.csv.partial";
    const std::string text = slurp(series);
    std::string edited = text;
    const auto row = edited.find('\n', edited.find("\ntime,") + 1) + 1;  // the first row of numbers
    const auto digit = edited.find_first_of("123456789", row);
    edited[digit] = edited[digit] == '9' ? '8' : static_cast<char>(edited[digit] + 1);
    std::ofstream(series, std::ios::binary) << edited;
    const auto refused = run("--quiet --resume " + dir.string());
    BOOST_TEST(refused.exit_code() == 1);
    BOOST_TEST(refused.err.find("is not what the checkpoint saved") != std::string::npos, refused.err);
    BOOST_TEST((slurp(series) == edited));  // left as it was found
    std::ofstream(series, std::ios::binary) << text;
    const auto resumed = run("--quiet --resume " + dir.string());
    BOOST_TEST(resumed.exit_code() == 0, resumed.err);
}

// On a full disk the program's own message comes first (VTK's log is not printed before it), the
// run exits 1, and no half-written file stays: the time series of a run without a checkpoint goes.
BOOST_AUTO_TEST_CASE(a_full_disk_is_told_first_and_leaves_nothing_half_written) {
    if (!mmtest::can_fill_a_disk()) {
        BOOST_WARN_MESSAGE(false, "this machine does not let a test mount a small disk (unshare -rm): not tested here");
        return;
    }
    const auto disk = work / "small_disk";
    const auto r = mmtest::run_on_a_small_disk(BIAXIAL, small_run + (with_vtk ? " --vtk-every 1" : "") + " --quiet --out " +
                                                            (disk / "run").string(),
                                               disk, with_vtk ? 160 : 24, work,
                                               "ls -A " + (disk / "run").string() + " > " + (work / "left.txt").string() +
                                                   "; find " + disk.string() + " -name \"*.partial*\" > " +
                                                   (work / "partial.txt").string());
    BOOST_TEST(r.exit_code() == 1, r.err);
    BOOST_TEST(first_line(r.err).rfind("biaxial: ", 0) == 0u, r.err);
    BOOST_TEST(r.err.find("cannot") != std::string::npos, r.err);
    BOOST_TEST(slurp(work / "partial.txt").empty(), slurp(work / "partial.txt"));
    BOOST_TEST(slurp(work / "left.txt").find("timeseries.csv") == std::string::npos, slurp(work / "left.txt"));
}

// A run larger than the machine is refused before any work, with the limit; a run says what it
// will cost before it starts (memory, the loading's steps and time, the frames' space).
BOOST_AUTO_TEST_CASE(the_cost_is_told_and_the_unaffordable_refused) {
    const auto dir = work / "cost";
    const auto told = run(small_run + (with_vtk ? " --vtk-every 5" : "") + " --out " + dir.string());
    BOOST_TEST_REQUIRE(told.exit_code() == 0, told.err);
    BOOST_TEST(first_line(told.out).rfind("biaxial 2D: 80 particles; about ", 0) == 0u, told.out);
    BOOST_TEST(first_line(told.out).find(" of memory; the loading ") != std::string::npos, told.out);
    if (with_vtk) BOOST_TEST(first_line(told.out).find(" VTK frames, about ") != std::string::npos, told.out);
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    if (static_cast<double>(pages) * static_cast<double>(page) < 30e9) {  // 1e8 disks need more
        const auto big = run("--particles 100000000 --quiet --out " + (work / "big").string());
        BOOST_TEST(big.exit_code() == 1);
        BOOST_TEST(big.err.find("of memory, more than this machine's") != std::string::npos, big.err);
        BOOST_TEST(big.err.find("use --particles <= ") != std::string::npos, big.err);
        BOOST_TEST(!fs::exists(work / "big"));
    }
    if (with_vtk) {  // 1e5 frames: said even with --quiet (the run is stopped after its first row)
        const auto many = run(" --preset quick --particles 80 --seed 7 --no-pictures --period 2 --output-interval 1e-5 --vtk-every 1 "
                              "--quiet --stop-after-rows 1 --out " + (work / "many").string());
        BOOST_TEST(many.exit_code() == 3, many.err);
        BOOST_TEST(many.out.find(" VTK frames, about 1.") != std::string::npos, many.out);  // 1e5 frames of 80 particles
        BOOST_TEST(first_line(many.out).find(" GB") != std::string::npos, many.out);
    }
    if (with_vtk && mmtest::can_fill_a_disk()) {  // more frames than the disk holds: refused, not started
        const auto disk = work / "frames_disk";
        const auto r = mmtest::run_on_a_small_disk(BIAXIAL, small_run + " --vtk-every 1 --quiet --out " + (disk / "run").string(), disk, 64,
                                                   work);
        BOOST_TEST(r.exit_code() == 1);
        BOOST_TEST(r.err.find("VTK frames of about") != std::string::npos, r.err);
        BOOST_TEST(r.err.find("use --vtk-every >= ") != std::string::npos, r.err);
    }
}

// Options given with --from-prepared act as run.json records them: the loading's time step
// follows --dt-fraction (not the prepared state's), and --wall-friction reaches the walls.
BOOST_AUTO_TEST_CASE(options_with_a_prepared_state_act_as_recorded) {
    const auto base = work / "base";
    BOOST_TEST_REQUIRE(run(small_run + " --quiet --out " + base.string()).exit_code() == 0);
    const std::string prepared = " --preset quick --period 0.02 --relax 0.002 --quiet --no-pictures --from-prepared " +
                                 (base / "prepared.state").string();
    const auto finer = work / "finer";
    BOOST_TEST_REQUIRE(run(prepared + " --dt-fraction 80 --out " + finer.string()).exit_code() == 0);
    const auto j = run_json(finer);
    BOOST_TEST(j["parameters"]["dt_fraction"].get<double>() == 80.0);
    const double tc = j["derived"]["contact_duration_s"].get<double>(), dt = j["derived"]["time_step_s"].get<double>();
    BOOST_TEST(std::abs(dt * 80.0 / tc - 1.0) < 1e-12, "dt = " << dt << " s, t_c = " << tc << " s");
    const auto rough = work / "rough";
    BOOST_TEST_REQUIRE(run(prepared + " --wall-friction --out " + rough.string()).exit_code() == 0);
    BOOST_TEST(run_json(rough)["parameters"]["wall_friction"].get<bool>());
    const auto smooth = work / "smooth";
    BOOST_TEST_REQUIRE(run(prepared + " --out " + smooth.string()).exit_code() == 0);
    BOOST_TEST((mmtest::rows_of(rough / "timeseries.csv") != mmtest::rows_of(smooth / "timeseries.csv")));  // friction acted on the walls
}
