#!/usr/bin/env bash
# The unit, physics, tools and example tests (the readers' fuzz loops included) built with GCC's
# AddressSanitizer and UndefinedBehaviorSanitizer in build-sanitize: a memory error, a leak or
# undefined behaviour stops the test that hit it. Left out: the benchmarks (their timings mean
# nothing here), the VTK part and the pictures (VTK's OpenGL under Xvfb; the build goes without
# VTK), the MPI layer's tests (OpenMPI's own allocations at exit read as leaks; the build goes
# without MPI), the checks of the source tree (header hygiene, layers, compile-fail, packaging:
# nothing of the library runs), the tiny speed-accuracy table (4-5 minutes here, the engine's
# code paths again) and the test cases labelled long (MICROMACRO_LONG_TESTS=OFF: long runs for
# their physics, of paths that shorter cases take too). On 2 cores: about half an hour to build
# (53 CPU-minutes of compiling) and 10 minutes to test (tools.biaxial, 4 minutes, is the longest).
#   scripts/sanitize.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build-sanitize}
jobs=${JOBS:-$(nproc)}
flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
# -O1 with line tables, as the sanitizers' manuals advise: readable reports, and faster to compile.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DMICROMACRO_WERROR=ON \
  -DMICROMACRO_WITH_VTK=OFF -DMICROMACRO_WITH_MPI=OFF -DMICROMACRO_TREE_CHECKS=OFF -DMICROMACRO_LONG_TESTS=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags"
cmake --build "$build" -j "$jobs"
export ASAN_OPTIONS=abort_on_error=1:detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
BOOST_TEST_COLOR_OUTPUT=no ctest --test-dir "$build" --output-on-failure -j "$jobs" -E "^((benchmark|viz)\..*|example\.speed_accuracy_tiny)$"
