#!/usr/bin/env bash
# Regenerates docs/performance.md's table from tests/benchmarks/throughput. The host is shared
# and its speed drifts by tens of percent within minutes, so the cases are run round-robin, RUNS
# rounds (default 9) of every case in turn, and each case's median is printed: a slow spell then
# falls on all cases alike instead of on the few that happened to run in it. A two-thread case's
# speed-up is the median over the rounds of its ratio to the one-thread run of the same case in the
# same round. Needs a build.
# With AGAINST=COMMIT every case runs side by side with that commit's throughput (built in a
# temporary git worktree), in alternating order within each round, and the table gives both
# medians and the median of the rounds' ratios (> 1: this build is faster); a case the other
# build cannot run (an option it does not have) says so. Prefix `taskset -c 1` to pin.
#   scripts/benchmarks.sh            # about 3 minutes on 2 cores
#   RUNS=5 scripts/benchmarks.sh     # about 2 minutes
#   AGAINST=7f47662 RUNS=5 taskset -c 1 scripts/benchmarks.sh
set -euo pipefail
cd "$(dirname "$0")/.."
tp=${BUILD_DIR:-build}/tests/benchmarks/throughput
[ -x "$tp" ] || { echo "benchmarks.sh: no $tp; build first (scripts/setup.sh test)" >&2; exit 1; }
repeats=${RUNS:-9}
[[ "$repeats" =~ ^[1-9][0-9]*$ ]] || { echo "benchmarks.sh: RUNS must be a positive whole number, not '$repeats'" >&2; exit 2; }
against=${AGAINST:-}
# dim particles law threads [extra options]
cases=(
  "2 1950 frictionless 1" "2 1950 frictional-no-rotation 1" "2 1950 frictional 1" "2 1950 frictional 1 --shear"
  "2 20000 frictional 1" "2 20000 frictional 2"
  "2 200000 frictionless 1" "2 200000 frictional-no-rotation 1" "2 200000 frictional 1" "2 200000 frictional 2"
  "2 200000 frictional 1 --precision float" "2 200000 frictional 1 --no-energy"
  "2 200000 frictional 1 --shuffle --no-auto-sort" "2 200000 frictional 1 --shuffle"
  "3 12500 frictional 1" "3 100000 frictionless 1" "3 100000 frictional-no-rotation 1" "3 100000 frictional 1"
  "3 100000 frictional 1 --shear" "3 100000 frictional 2"
  "3 100000 frictional 1 --precision float" "3 100000 frictional 1 --no-energy"
  "3 100000 frictional 1 --shuffle --no-auto-sort" "3 100000 frictional 1 --shuffle"
)
out=$(mktemp -d) tree=""
trap 'rm -rf "$out"; [ -z "$tree" ] || git worktree remove --force "$tree" >/dev/null 2>&1 || true' EXIT
if [ -n "$against" ]; then
  tree=$(mktemp -d)
  git worktree add -q -f --detach "$tree" "$against"
  cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$tree/build" -j2 --target throughput >/dev/null
  other=$tree/build/tests/benchmarks/throughput
fi
# run_case BINARY CASE OUTPUT: one timing, appended as a JSON line ("failed" if the binary
# refuses the case's options).
run_case() {
  local dim n law threads extra steps
  read -r dim n law threads extra <<<"$2"
  steps=$(( (dim == 2 ? 20000000 : 6000000) / n ))
  [ "$steps" -lt 20 ] && steps=20
  # shellcheck disable=SC2086  # extra holds several options
  "$1" --dim "$dim" --particles "$n" --law "$law" --threads "$threads" --steps "$steps" $extra --json >>"$3" 2>/dev/null ||
    echo failed >>"$3"
}
for round in $(seq "$repeats"); do
  for k in "${!cases[@]}"; do
    if [ -z "$against" ]; then
      run_case "$tp" "${cases[$k]}" "$out/$k"
    elif (( (round + k) % 2 )); then
      run_case "$tp" "${cases[$k]}" "$out/$k"; run_case "$other" "${cases[$k]}" "$out/other$k"
    else
      run_case "$other" "${cases[$k]}" "$out/other$k"; run_case "$tp" "${cases[$k]}" "$out/$k"
    fi
  done
  echo "round $round of $repeats done" >&2
done
field() { grep -o "\"$1\": [0-9.e+]*" "$2" | awk '{print $2}'; }
median() { sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
if [ -n "$against" ]; then
  echo "$tp against $against ($(git rev-parse --short "$against")), $repeats rounds, alternating"
  echo
  echo "| case | particles | threads | this build (particle-steps/s, median) | $against | ratio (median of rounds) |"
  echo "|---|---|---|---|---|---|"
  for k in "${!cases[@]}"; do
    read -r dim n law threads extra <<<"${cases[$k]}"
    speed() { if grep -q failed "$1"; then echo "cannot run these options"; else field particle_steps_per_second "$1" | median | awk '{printf "%.3g", $1}'; fi; }
    ratio=""
    grep -q failed "$out/other$k" "$out/$k" ||
      ratio=$(paste <(field particle_steps_per_second "$out/$k") <(field particle_steps_per_second "$out/other$k") |
        awk '{print $1 / $2}' | median | awk '{printf "%.3f", $1}')
    printf '| %dD %s%s | %d | %d | %s | %s | %s |\n' "$dim" "$law" "${extra:+ $extra}" "$n" "$threads" "$(speed "$out/$k")" \
      "$(speed "$out/other$k")" "$ratio"
  done
  exit 0
fi
fma=$(grep -o '"fma": [a-z]*' "$out/0" | head -1 | awk '{print $2}')
echo "$tp, fused multiply-adds (MICROMACRO_FMA): $fma"
echo
echo "| case | particles | contacts per particle | threads | particle-steps/s (median of $repeats) | speed-up over one thread | ns per contact | engine bytes per particle | peak RSS bytes per particle |"
echo "|---|---|---|---|---|---|---|---|---|"
for k in "${!cases[@]}"; do
  read -r dim n law threads extra <<<"${cases[$k]}"
  speedup=""
  if [ "$threads" -gt 1 ]; then  # the one-thread case with the same options, round by round
    for j in "${!cases[@]}"; do
      [ "${cases[$j]}" = "$dim $n $law 1${extra:+ $extra}" ] || continue
      speedup=$(paste <(field particle_steps_per_second "$out/$k") <(field particle_steps_per_second "$out/$j") |
        awk '{print $1 / $2}' | median | awk '{printf "%.2fx", $1}')
    done
  fi
  case "$extra" in
    *shear*) label=" (shear)" ;;
    *float*) label=", float storage" ;;
    *shuffle*no-auto-sort*) label=", particles in random order" ;;
    *shuffle*) label=", shuffled, sorted by the engine" ;;
    *no-energy*) label=", energy books off" ;;
    *) label="" ;;
  esac
  contacts=$(field contacts "$out/$k" | head -1)
  printf '| %dD %s%s | %d | %.2f | %d | %.3g | %s | %.1f | %.0f | %.0f |\n' "$dim" "${law/-no-rotation/ without rotation}" "$label" "$n" \
    "$(echo "2 * $contacts / $n" | bc -l)" "$threads" "$(field particle_steps_per_second "$out/$k" | median)" "$speedup" \
    "$(field ns_per_contact "$out/$k" | median)" "$(field storage_bytes_per_particle "$out/$k" | head -1)" \
    "$(field bytes_per_particle "$out/$k" | head -1)"
done
