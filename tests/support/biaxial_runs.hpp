#pragma once
// What the tests of the biaxial program share: whether it was built with VTK (BIAXIAL_WITH_VTK),
// running it (BIAXIAL, the program's path) without its pictures, and a time series' rows without
// the line that names the run. Define BIAXIAL before including.
#include <filesystem>
#include <string>

#include "support/programs.hpp"

namespace mmtest {

#ifdef BIAXIAL_WITH_VTK
inline constexpr bool biaxial_with_vtk = true;  // the program writes VTK frames
#else
inline constexpr bool biaxial_with_vtk = false;
#endif

/// Runs the biaxial program in `work` without the pictures, which it would otherwise make through
/// Xvfb at the end of every run (tests/tools/biaxial.cpp's `pictures_without_a_display` makes them).
inline ProgramResult run_biaxial(const std::string& args, const std::filesystem::path& work) {
    return run_program(BIAXIAL, args.find("--no-pictures") == std::string::npos ? args + " --no-pictures" : args, work);
}

/// A time series without its first line, "# run <id>", which names the run and so differs
/// between any two runs.
inline std::string rows_of(const std::filesystem::path& csv) {
    const std::string text = slurp(csv);
    if (text.rfind("# run ", 0) != 0) return "no run id line in " + csv.string();
    return text.substr(text.find('\n') + 1);
}

}  // namespace mmtest
