#pragma once
// Running a program of the project from a test: its exit status and what it printed.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace mmtest {

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

struct ProgramResult {
    int status;
    std::string out, err;
};

/// Runs `program args` with standard output and error captured in files under `work`.
inline ProgramResult run_program(const std::string& program, const std::string& args, const std::filesystem::path& work) {
    std::filesystem::create_directories(work);
    const auto out = work / "stdout.txt", err = work / "stderr.txt";
    const int status = std::system((program + " " + args + " > " + out.string() + " 2> " + err.string()).c_str());
    return {status, slurp(out), slurp(err)};
}

}  // namespace mmtest
