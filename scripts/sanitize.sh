#!/usr/bin/env bash
# The unit, physics, I/O and tools tests (the readers' fuzz loops included) built with GCC's
# AddressSanitizer and UndefinedBehaviorSanitizer in build-sanitize: a memory error, a leak or
# undefined behaviour stops the test that hit it. Left out: the benchmarks (their timings mean
# nothing here), the pictures (VTK's OpenGL under Xvfb), the compile-fail and package checks
# (nothing runs).
#   scripts/sanitize.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build-sanitize}
jobs=${JOBS:-$(nproc)}
flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMICROMACRO_WERROR=ON -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="$flags"
cmake --build "$build" -j "$jobs"
export ASAN_OPTIONS=abort_on_error=1:detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
BOOST_TEST_COLOR_OUTPUT=no ctest --test-dir "$build" --output-on-failure -j "$jobs" -E "^(benchmark|viz|compile_fail|package)\."
