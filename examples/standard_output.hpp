#pragma once
// Whether what a program printed reached standard output. A full disk or a closed pipe shows only
// when the buffers are flushed, and a program that then exits 0 would report success for a
// result nobody received (tests/tools/exit_status.cpp checks the programs on /dev/full).
#include <cstdio>
#include <iostream>

/// Flushes standard output, through iostreams and stdio alike, and tells whether everything
/// written to it arrived.
inline bool standard_output_complete() {
    std::cout.flush();
    return static_cast<bool>(std::cout) && std::fflush(stdout) == 0 && !std::ferror(stdout);
}
