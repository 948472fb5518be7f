#pragma once
// Running a program of the project from a test: its exit status and what it printed.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../../examples/installed.hpp"

namespace mmtest {

using ::installed;  // whether a program the tests call (ffmpeg, xvfb-run) is on the PATH

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Writes `text` to the file `name` in `dir` (created if needed) and returns its path: the input
/// files the tests hand to programs and readers.
inline std::string write_file(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
    std::filesystem::create_directories(dir);
    const auto path = dir / name;
    std::ofstream(path) << text;
    return path.string();
}

/// A fresh, empty work folder of this test process under the system's temporary folder: `name`
/// plus the process id, so that two test processes (two builds tested at once, say) never share
/// one. Removed when the object goes: at the end of the process for one at namespace scope.
struct WorkFolder {
    std::filesystem::path path;
    explicit WorkFolder(const std::string& name)
        : path(std::filesystem::temp_directory_path() / (name + "." + std::to_string(::getpid()))) {
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~WorkFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    WorkFolder(const WorkFolder&) = delete;
    WorkFolder& operator=(const WorkFolder&) = delete;
};

struct ProgramResult {
    int status;     ///< as std::system returns it: 0 for success
    std::string out, err;
    /// The program's exit status (WEXITSTATUS), or -1 if it did not exit normally.
    int exit_code() const { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }
};

/// Runs `program args` with standard output and error captured in files under `work`.
inline ProgramResult run_program(const std::string& program, const std::string& args, const std::filesystem::path& work) {
    std::filesystem::create_directories(work);
    const auto out = work / "stdout.txt", err = work / "stderr.txt";
    const int status = std::system((program + " " + args + " > " + out.string() + " 2> " + err.string()).c_str());
    return {status, slurp(out), slurp(err)};
}

}  // namespace mmtest
