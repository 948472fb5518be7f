#!/usr/bin/env bash
# The test set "sanitize" (tests/CMakeLists.txt: every unit test, the readers' fuzz loops among
# them, the physics tests and the examples' self-checks) built with AddressSanitizer and
# UndefinedBehaviorSanitizer in build-sanitize: a memory error, a leak or undefined behaviour
# stops the test that hit it. Built with clang, whose sanitizers compile this code about 2.5
# times faster than GCC's (tests/physics/collision.cpp: 37 s against 94 s); Debian's clang 14,
# its runtime (libclang-rt-14-dev) and its OpenMP (libomp-14-dev) are installed if missing.
# Without the test cases labelled long (MICROMACRO_LONG_TESTS=OFF: long runs for their physics,
# of code paths that shorter cases take too). The programs' own tests (tools, viz, MPI) run in
# the default build.
#   scripts/sanitize.sh
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_packages.sh clang libclang-rt-14-dev libomp-14-dev
build=${BUILD_DIR:-build-sanitize}
jobs=${JOBS:-$(nproc)}
flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
# -O1 with line tables, as the sanitizers' manuals advise: readable reports, and faster to compile.
# Without fused multiply-adds: the tests that compare two code paths to the bit assert it with
# FMA only of GCC's contraction (clang fuses run(n)'s merged kick otherwise than step()'s), and
# without FMA of any compiler's.
CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DMICROMACRO_WERROR=ON -DMICROMACRO_FMA=OFF -DMICROMACRO_WITH_VTK=OFF -DMICROMACRO_WITH_MPI=OFF -DMICROMACRO_TREE_CHECKS=OFF \
  -DMICROMACRO_LONG_TESTS=OFF -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags"
cmake --build "$build" -j "$jobs" --target tests_sanitize
export ASAN_OPTIONS=abort_on_error=1:detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
BOOST_TEST_COLOR_OUTPUT=no ctest --test-dir "$build" --output-on-failure -j "$jobs" -L '^sanitize$'
