#!/usr/bin/env bash
# One-command set-up for a fresh Debian 12 machine.
#   scripts/setup.sh run    install what is missing, build, run the project's main job
#                           (the biaxial test, quick preset, into runs/quick or $OUT)
#   scripts/setup.sh test   install what is missing, build, run the whole test suite
# Environment: BUILD_DIR (default build), JOBS (default: number of cores), CMAKE_ARGS (more
# configure options, e.g. CMAKE_ARGS=-DMICROMACRO_FMA=OFF with BUILD_DIR=build-no-fma).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-}
case "$mode" in run|test) ;; *) echo "usage: scripts/setup.sh run|test" >&2; exit 2 ;; esac

packages=(build-essential cmake libeigen3-dev libboost-test-dev libcli11-dev nlohmann-json3-dev libvtk9-dev xvfb xauth
          libopenmpi-dev openmpi-bin)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing Debian packages: ${missing[*]}"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}
read -r -a cmake_args <<<"${CMAKE_ARGS:-}"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DMICROMACRO_WERROR=ON "${cmake_args[@]}"
cmake --build "$build" -j "$jobs"

if [ "$mode" = run ]; then
  out=${OUT:-runs/quick}
  "$build/examples/biaxial" --preset quick --out "$out" --overwrite  # this script's demo run, replaced each time
  echo "time series: $out/timeseries.csv   parameters and timing: $out/run.json"
else
  BOOST_TEST_COLOR_OUTPUT=no ctest --test-dir "$build" --output-on-failure -j "$jobs"
fi
