// The README's promise for every program of this build ("Errors and exit status"): --help prints
// the usage and exits 0; an unknown option exits 1 with a message; an input that is not there
// exits 1 with a message naming it, and writes nothing.
#define BOOST_TEST_MODULE exit status of every program
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <map>
#include <string>

#include "programs_built.hpp"
#include "support/programs.hpp"

namespace fs = std::filesystem;

namespace {

const mmtest::WorkFolder work_folder("micromacro_exit_status");  // removed when the test process ends
const fs::path& work = work_folder.path;
const std::string missing = "/nonexistent_micromacro_input";

struct Expectation {
    std::string missing_input_args;  ///< arguments that name an input that is not there
};

// For each program, how it is handed an input that does not exist (an output folder or file in
// `work` where it needs one, so that only the input can be at fault).
std::map<std::string, Expectation> expectations() {
    const std::string out = (work / "out").string();
    return {
        {"biaxial", {"--quiet --from-prepared " + missing + "/prepared.state --out " + out}},
        {"biaxial_mpi", {"--quiet --from-prepared " + missing + "/prepared.state --out " + out}},  // one rank, without mpirun
        {"biaxial_summary", {missing + "/run"}},
        {"analyze_packing", {missing + "/packing.csv"}},
        {"speed_accuracy", {"--seeds 0 --out-dir " + out}},  // reads no file: an absurd count instead
        {"oblique_impacts", {"--out " + missing + "/oblique.md"}},  // reads no file: an unwritable output
        {"01_two_particles", {"notanumber"}},
        {"02_custom_contact_law", {"notanumber"}},
        {"03_element_test", {"notanumber"}},
        {"element_test", {"--quiet --from-prepared " + missing + "/prepared.state --out " + out}},
        {"throughput", {"--packing " + missing + "/packing.csv"}},
        {"random_packing", {"--particles 20 --out " + missing + "/packing.dump"}},  // reads no file: an unwritable output
        {"render_snapshot", {missing + "/particles_0.vtp -o " + (work / "picture.png").string()}},
        {"plot_timeseries", {missing + "/timeseries.csv --out " + (work / "plots").string()}},
    };
}

}  // namespace

BOOST_AUTO_TEST_CASE(every_program_keeps_the_promise) {
    const auto table = expectations();
    BOOST_TEST(std::size(programs_built) >= 6u);  // the CLI11 programs are always built with the tests
    for (const auto& [name, path] : programs_built) {
        BOOST_TEST_CONTEXT(name) {
            BOOST_REQUIRE(table.count(name) == 1u);
            const Expectation& e = table.at(name);
            fs::remove_all(work);

            const auto help = mmtest::run_program(path, "--help", work);
            BOOST_TEST(help.exit_code() == 0);
            BOOST_TEST((help.out.find("sage") != std::string::npos), help.out);  // "Usage" / "usage"

            if (std::string(name).rfind("0", 0) != 0) {  // the numbered examples take no options
                const auto unknown = mmtest::run_program(path, "--no-such-option", work);
                BOOST_TEST(unknown.exit_code() == 1);
                BOOST_TEST(!unknown.err.empty());
            }

            const auto bad = mmtest::run_program(path, e.missing_input_args, work);
            BOOST_TEST(bad.exit_code() == 1, bad.err);
            BOOST_TEST(!bad.err.empty());
            const bool names_it = bad.err.find(missing) != std::string::npos || bad.err.find("--seeds") != std::string::npos ||
                                  bad.err.find("notanumber") != std::string::npos;
            BOOST_TEST(names_it, bad.err);
            BOOST_TEST(!fs::exists(work / "out"));  // nothing written
            BOOST_TEST(!fs::exists(work / "picture.png"));
            BOOST_TEST(!fs::exists(work / "plots"));
        }
    }
}

// A number outside its option's rule is refused by name, value and rule, before anything is
// written: not CLI11's own range up to 1.8e308, and never nan or inf taken as given (throughput
// ran with its default skin for --skin nan) or passed to a plot as a scale.
BOOST_AUTO_TEST_CASE(a_number_outside_its_rule_is_refused_by_name_value_and_rule) {
    const std::string out = (work / "out").string();
    const std::multimap<std::string, std::pair<std::string, std::string>> cases = {  // program, (arguments, what the rule says)
        {"throughput", {"--skin nan", "--skin: nan is not a finite number above 0"}},
        {"throughput", {"--dt 0", "--dt: 0 is not a finite number above 0"}},
        {"throughput", {"--dt-fraction inf", "--dt-fraction: inf is not a finite number above 0"}},
        {"random_packing", {"--k 0 --out " + out, "--k: 0 is not a finite number above 0"}},
        {"random_packing", {"--gamma-n -1 --out " + out, "--gamma-n: -1 is not a finite number of 0 or more"}},
        {"random_packing", {"--pressure nan --out " + out, "--pressure: nan is not a finite number from 1e-06 to 0.01"}},
        {"plot_timeseries", {"timeseries.csv --k nan --out " + out, "--k: nan is not a finite number above 0"}},
        {"plot_timeseries", {"timeseries.csv --kt-ratio 0 --out " + out, "--kt-ratio: 0 is not a finite number above 0"}},
        // A count another option would replace silently is refused with the reason.
        {"speed_accuracy", {"--tiny --particles 0 --out-dir " + out, "--tiny runs 40 particles and would ignore --particles 0"}},
    };
    std::size_t checked = 0;
    for (const auto& [name, path] : programs_built) {
        for (auto [c, end] = cases.equal_range(name); c != end; ++c) {
            BOOST_TEST_CONTEXT(name << " " << c->second.first) {
                fs::remove_all(work);
                const auto refused = mmtest::run_program(path, c->second.first, work);
                BOOST_TEST(refused.exit_code() == 1);
                BOOST_TEST(refused.err.find(c->second.second) != std::string::npos, refused.err);
                BOOST_TEST(refused.err.find("1797693") == std::string::npos, refused.err);
                BOOST_TEST(!fs::exists(work / "out"));
                ++checked;
            }
        }
    }
    BOOST_TEST(checked >= 6u);  // throughput and random_packing are always built with the tests
}

// An empty value is a missing value, never 0 (`--mu ''` ran frictionless), in either form; an
// option given twice is named with the fix; each message starts with the program's name.
BOOST_AUTO_TEST_CASE(an_empty_or_repeated_value_is_refused) {
    const std::map<std::string, std::string> option_of = {  // an option of each program that takes one value, and a value
        {"biaxial", "--mu 0.5"},          {"biaxial_mpi", "--mu 0.5"},       {"analyze_packing", "--k 1e5"}, {"element_test", "--mu 0.5"},
        {"speed_accuracy", "--seeds 1"},  {"oblique_impacts", "--phases 1"}, {"throughput", "--particles 100"},
        {"random_packing", "--particles 20"}, {"render_snapshot", "--step 0"}, {"plot_timeseries", "--k 1e5"},
    };
    std::size_t checked = 0;
    for (const auto& [name, path] : programs_built) {
        BOOST_TEST_CONTEXT(name) {
            if (std::string(name) == "biaxial_summary") {  // one argument, the run folder
                const auto empty = mmtest::run_program(path, "''", work);
                BOOST_TEST(empty.exit_code() == 1);
                BOOST_TEST(empty.err.rfind("biaxial_summary: the run directory is empty", 0) == 0u, empty.err);
                continue;
            }
            const auto o = option_of.find(name);
            if (o == option_of.end()) continue;  // 01 and 02 take no options (their bad argument is above)
            const std::string option = o->second.substr(0, o->second.find(' '));
            for (const std::string& args : {option + " ''", option + "="}) {
                fs::remove_all(work);
                const auto empty = mmtest::run_program(path, args + " --out " + (work / "out").string(), work);
                BOOST_TEST(empty.exit_code() == 1, args);
                BOOST_TEST(empty.err.rfind(std::string(name) + ": " + option + ": ", 0) == 0u, args << ": " << empty.err);
                BOOST_TEST(empty.err.find("empty") != std::string::npos, args << ": " << empty.err);
                BOOST_TEST(!fs::exists(work / "out"));
            }
            const auto twice = mmtest::run_program(path, o->second + " " + o->second, work);
            BOOST_TEST(twice.exit_code() == 1);
            BOOST_TEST(twice.err.rfind(std::string(name) + ": " + option + " was given 2 times; give it once", 0) == 0u, twice.err);
            ++checked;
        }
    }
    BOOST_TEST(checked >= 4u);  // the CLI11 programs always built with the tests
}

// An input that exists but is not a file (here a folder) is called that, not missing.
BOOST_AUTO_TEST_CASE(an_input_that_is_not_a_file_is_called_so) {
    fs::remove_all(work);
    const fs::path folder = work / "a_folder";
    fs::create_directories(folder);
    for (const auto& [name, path] : programs_built) {
        std::string args;
        if (std::string(name) == "render_snapshot") args = folder.string() + " -o " + (work / "picture.png").string();
        else if (std::string(name) == "plot_timeseries") args = folder.string() + " --out " + (work / "plots").string();
        else continue;
        const auto r = mmtest::run_program(path, args, work);
        BOOST_TEST(r.exit_code() == 1, name);
        BOOST_TEST(r.err.find("cannot read " + folder.string() + ": not a regular file") != std::string::npos, name << ": " << r.err);
    }
}

// A result that cannot be written is an error: standard output on a full disk (/dev/full).
BOOST_AUTO_TEST_CASE(a_full_standard_output_is_an_error) {
    fs::remove_all(work);
    std::map<std::string, std::string> path_of(std::begin(programs_built), std::end(programs_built));
    for (const auto& [name, path] : programs_built) {
        std::string args;
        if (std::string(name) == "throughput") args = "--particles 100 --steps 2 --json";
        else if (std::string(name) == "analyze_packing")
            args = mmtest::write_file(work, "three.csv", "x,z,r\n0,0,1e-3\n2e-3,0,1e-3\n4e-3,0,1e-3\n");
        else if (std::string(name) == "biaxial_summary" && path_of.count("biaxial")) {  // on a real run, a short one
            const auto run = work / "run";
            const auto made = mmtest::run_program(path_of["biaxial"], "--preset quick --particles 60 --period 0.01 --relax 0.002 "
                                                  "--quiet --no-pictures --vtk-every 0 --out " + run.string(), work);
            BOOST_TEST_REQUIRE(made.exit_code() == 0, made.err);
            const auto table = mmtest::run_program(path, run.string(), work);  // the table itself is fine
            BOOST_TEST(table.exit_code() == 0, table.err);
            BOOST_TEST(table.out.find("| cost |") != std::string::npos, table.out);
            args = run.string();
        } else {
            continue;  // the others write files; their stdout is a progress line
        }
        BOOST_TEST_CONTEXT(name) {
            const int status = std::system((std::string(path) + " " + args + " > /dev/full 2> " + (work / "err.txt").string()).c_str());
            BOOST_TEST(WIFEXITED(status));
            BOOST_TEST(WEXITSTATUS(status) == 1);
            BOOST_TEST(mmtest::slurp(work / "err.txt").find("standard output") != std::string::npos);
        }
    }
}
