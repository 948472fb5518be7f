#!/usr/bin/env bash
# Compares this build's tests/benchmarks/throughput (or examples/biaxial) with another commit's,
# side by side: the other commit is built in a temporary git worktree, the two binaries alternate
# REPS times (which one goes first alternates too; the machines are shared and noisy, so only
# runs taken together compare), and the medians, their ratio and the median of the ratios of
# each back-to-back pair are printed. How the "side by side" figures of docs/performance.md
# were taken.
#   scripts/side_by_side.sh COMMIT "--dim 3 --particles 100000 --steps 60" [REPS=5]
#   PROGRAM=biaxial scripts/side_by_side.sh COMMIT "--preset paper --vtk-every 0" 2
# throughput compares particle-steps per second (ratio > 1: this build is faster); biaxial
# compares the wall seconds of whole runs (each into a temporary directory, no pictures;
# ratio < 1: this build is faster). OTHER_CMAKE_ARGS configures the other commit's build, e.g.
#   OTHER_CMAKE_ARGS=-DMICROMACRO_FMA=OFF scripts/side_by_side.sh HEAD "ARGS" 9
# times this build against the same commit without fused multiply-adds, and OTHER_ARGS gives the
# other build its own options, e.g.
#   OTHER_ARGS="--dim 3 --particles 100000 --steps 60 --shuffle --no-auto-sort" \
#     scripts/side_by_side.sh HEAD "--dim 3 --particles 100000 --steps 60 --shuffle" 7
# times the engine's own sorting against the shuffled order kept. Prefix `taskset -c 1` to pin
# both programs to one core (the pinned figures of docs/performance.md).
set -euo pipefail
cd "$(dirname "$0")/.."
commit=$1 args=$2 reps=${3:-5}
other_args=${OTHER_ARGS:-$args}
program=${PROGRAM:-throughput}
case "$program" in
  throughput) target=tests/benchmarks/throughput ;;
  biaxial) target=examples/biaxial ;;
  *) echo "side_by_side.sh: PROGRAM must be throughput or biaxial, not '$program'" >&2; exit 2 ;;
esac
new=${BUILD_DIR:-build}/$target
[ -x "$new" ] || { echo "side_by_side.sh: no $new; build first (scripts/setup.sh test)" >&2; exit 1; }
tree=$(mktemp -d) out=$(mktemp -d)
trap 'git worktree remove --force "$tree" >/dev/null 2>&1 || true; rm -rf "$out"' EXIT
git worktree add -q -f --detach "$tree" "$commit"
read -r -a other_cmake_args <<<"${OTHER_CMAKE_ARGS:-}"
cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE=Release "${other_cmake_args[@]}" >/dev/null
cmake --build "$tree/build" -j2 --target "$program" >/dev/null
old=$tree/build/$target
measure() {  # measure BINARY ARGS
  local args=$2
  if [ "$program" = throughput ]; then
    "$1" $args --json | grep -o '"particle_steps_per_second": [0-9.e+]*' | awk '{print $2}'
  else
    rm -rf "$out/run"
    local start end
    start=$(date +%s.%N)
    "$1" $args --out "$out/run" --no-pictures --quiet >/dev/null
    end=$(date +%s.%N)
    awk -v a="$start" -v b="$end" 'BEGIN {printf "%.2f\n", b - a}'
  fi
}
median() { sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
o=() n=() q=()
for k in $(seq "$reps"); do
  if ((k % 2)); then a=$(measure "$old" "$other_args"); b=$(measure "$new" "$args"); else b=$(measure "$new" "$args"); a=$(measure "$old" "$other_args"); fi
  o+=("$a") n+=("$b") q+=("$(awk -v x="$b" -v y="$a" 'BEGIN {print x / y}')")
done
mo=$(printf '%s\n' "${o[@]}" | median) mn=$(printf '%s\n' "${n[@]}" | median) mq=$(printf '%s\n' "${q[@]}" | median)
unit="particle-steps/s"
[ "$program" = biaxial ] && unit="s"
echo "$program $args ($unit): $commit${OTHER_CMAKE_ARGS:+ ($OTHER_CMAKE_ARGS)}${OTHER_ARGS:+ with $OTHER_ARGS} ${o[*]}; this build ${n[*]}"
echo "medians $mo and $mn, ratio $(awk -v a="$mn" -v b="$mo" 'BEGIN {printf "%.3f", a / b}'); median of the pairs' ratios $(awk -v q="$mq" 'BEGIN {printf "%.3f", q}') ($reps pairs)"
