#!/usr/bin/env bash
# One-command set-up for a fresh Debian 12 machine.
#   scripts/setup.sh run    install what is missing, build what the main job needs (the biaxial
#                           program and the picture tools), run it (the biaxial test, quick
#                           preset, with its plots, snapshots and movie, into runs/quick or $OUT)
#   scripts/setup.sh test   install what is missing, build everything, run the whole test suite
# Environment: BUILD_DIR (default build), JOBS (default: number of cores), CMAKE_ARGS (more
# configure options, e.g. CMAKE_ARGS=-DMICROMACRO_FMA=OFF with BUILD_DIR=build-no-fma).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-}
case "$mode" in run|test) ;; *) echo "usage: scripts/setup.sh run|test" >&2; exit 2 ;; esac

scripts/install_packages.sh build-essential cmake libeigen3-dev libboost-test-dev libcli11-dev nlohmann-json3-dev libvtk9-dev \
  xvfb xauth ffmpeg libopenmpi-dev openmpi-bin

build=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}
read -r -a cmake_args <<<"${CMAKE_ARGS:-}"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DMICROMACRO_WERROR=ON "${cmake_args[@]}"

if [ "$mode" = run ]; then
  cmake --build "$build" -j "$jobs" --target main_job  # biaxial, render_snapshot, plot_timeseries: not the tests
  out=${OUT:-runs/quick}
  "$build/examples/biaxial" --preset quick --out "$out" --overwrite  # this script's demo run, replaced each time
  echo "time series: $out/timeseries.csv   parameters and timing: $out/run.json"
else
  cmake --build "$build" -j "$jobs"
  BOOST_TEST_COLOR_OUTPUT=no ctest --test-dir "$build" --output-on-failure -j "$jobs"
fi
