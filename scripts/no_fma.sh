#!/usr/bin/env bash
# The tests whose assertions contraction can change and that the sanitizer build (scripts/sanitize.sh,
# also without fused multiply-adds) does not run: the test set "bits", tests/CMakeLists.txt: the
# thread counts' long case, rank counts compared to the bit, the biaxial program over ranks, the
# benchmark's record of its build. Built without fused multiply-adds in build-no-fma: the build
# that gives the same bits on any CPU (README, "Using the library"). Every test also runs in the
# default build, with fused multiply-adds (scripts/setup.sh test).
#   scripts/no_fma.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build-no-fma}
jobs=${JOBS:-$(nproc)}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DMICROMACRO_WERROR=ON -DMICROMACRO_FMA=OFF -DMICROMACRO_TREE_CHECKS=OFF \
  -DMICROMACRO_WITH_VTK=OFF
cmake --build "$build" -j "$jobs" --target tests_bits
BOOST_TEST_COLOR_OUTPUT=no ctest --test-dir "$build" --output-on-failure -j "$jobs" -L '^bits$'
