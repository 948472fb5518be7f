#pragma once
// Whether a program is installed (on the PATH), asked of the shell that will run it: the programs
// here use ffmpeg and xvfb-run when they are there and say what to install when not.
#include <cstdlib>
#include <string>

inline bool installed(const std::string& program) {
    return std::system(("command -v " + program + " > /dev/null 2>&1").c_str()) == 0;
}
