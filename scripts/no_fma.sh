#!/usr/bin/env bash
# The tests whose assertions contraction can change (the test set "bits", tests/CMakeLists.txt:
# two code paths, thread counts and rank counts compared to the bit, the benchmark's record of its
# build), built without fused multiply-adds in build-no-fma: the build that gives the same bits
# on any CPU (README, "Using the library"). Every other test's answer does not depend on
# contraction and runs in the default build (scripts/setup.sh test).
#   scripts/no_fma.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build-no-fma}
jobs=${JOBS:-$(nproc)}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DMICROMACRO_WERROR=ON -DMICROMACRO_FMA=OFF -DMICROMACRO_TREE_CHECKS=OFF \
  -DMICROMACRO_WITH_VTK=OFF
cmake --build "$build" -j "$jobs" --target tests_bits
BOOST_TEST_COLOR_OUTPUT=no ctest --test-dir "$build" --output-on-failure -j "$jobs" -L '^bits$'
