#!/usr/bin/env bash
# Where a build's time goes: configures BUILD_DIR (default build-times) with a compiler launcher
# that logs the wall seconds of each translation unit, builds TARGET (default all) on JOBS cores,
# and prints the units by time and their sums by folder. Extra configure options in CMAKE_ARGS
# (e.g. those of scripts/no_fma.sh or scripts/sanitize.sh). docs/ci.md holds its output.
#   scripts/compile_times.sh
#   TARGET=tests_sanitize CC=clang CXX=clang++ CMAKE_ARGS="..." scripts/compile_times.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build-times}
jobs=${JOBS:-$(nproc)}
read -r -a cmake_args <<<"${CMAKE_ARGS:-}"
mkdir -p "$build"
log=$(realpath "$build")/compile_times.log
launcher=$(realpath "$build")/timed_compile.sh
cat >"$launcher" <<'WRAP'
#!/usr/bin/env bash
# Runs one compile and appends "seconds object" to $COMPILE_TIMES_LOG.
start=$(date +%s.%N)
"$@"
status=$?
out=""; previous=""
for a in "$@"; do [ "$previous" = "-o" ] && out=$a; previous=$a; done
echo "$(echo "$(date +%s.%N) - $start" | bc) $out" >>"$COMPILE_TIMES_LOG"
exit $status
WRAP
chmod +x "$launcher"
rm -f "$log"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DMICROMACRO_WERROR=ON -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" "${cmake_args[@]}" >/dev/null
start=$SECONDS
COMPILE_TIMES_LOG=$log cmake --build "$build" -j "$jobs" --target "${TARGET:-all}" >/dev/null
wall=$((SECONDS - start))
echo "## $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $jobs jobs, target ${TARGET:-all}: $wall s wall"
echo
awk '{ s += $1 } END { printf "%d translation units, %.0f CPU seconds of compiling\n\n", NR, s }' "$log"
echo "| seconds | translation unit |"
echo "|---|---|"
sort -rn "$log" | head -25 | awk '{ sub(/.*CMakeFiles\//, "", $2); sub(/\.dir\//, ": ", $2); printf "| %.1f | %s |\n", $1, $2 }'
echo
echo "| seconds | units | group |"
echo "|---|---|---|"
awk '{ g = $2; sub(/.*CMakeFiles\//, "", g); sub(/\.dir\/.*/, "", g)
       if (g ~ /^test_mpi/) g = "tests/mpi"; else if (g ~ /^test_physics/) g = "tests/physics"
       else if (g ~ /^test_unit/) g = "tests/unit"; else if (g ~ /^test_(tools|viz|io)_/) g = "tests/tools, viz, io"
       else if (g == "header_hygiene") g = "header hygiene"; else g = "programs (examples, viz, benchmarks)"
       s[g] += $1; n[g]++ } END { for (g in s) printf "| %.0f | %d | %s |\n", s[g], n[g], g }' "$log" | sort -t'|' -k2 -rn
