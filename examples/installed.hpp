#pragma once
// Where the programs a program calls are: on the PATH (ffmpeg and xvfb-run, used when they are
// there, with what to install said when not), or the project's own next to the caller.
#include <cstdlib>
#include <filesystem>
#include <string>

inline bool installed(const std::string& program) {
    return std::system(("command -v " + program + " > /dev/null 2>&1").c_str()) == 0;
}

namespace micromacro::cli {

/// A program of the project next to this one: installed in the same directory, or in the build
/// tree's viz/ beside examples/. Empty if not found.
inline std::filesystem::path sibling_program(const std::string& name) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path self = fs::canonical("/proc/self/exe", ec).parent_path();
    for (const fs::path& candidate : {self / name, self.parent_path() / "viz" / name})
        if (fs::is_regular_file(candidate, ec)) return candidate;
    return {};
}

}  // namespace micromacro::cli
