#!/usr/bin/env bash
# Regenerates the README's performance table: each case of tests/benchmarks/throughput run RUNS
# times (default 9), the median printed (the machines are shared and noisy). A two-thread case
# alternates with the same case on one thread, and its speed-up is the median of the back-to-back
# ratios (not the ratio of two rows, taken minutes apart). Needs a build.
#   scripts/benchmarks.sh            # about 4 minutes on 2 cores
#   RUNS=5 scripts/benchmarks.sh     # about 2 minutes
set -euo pipefail
cd "$(dirname "$0")/.."
tp=${BUILD_DIR:-build}/tests/benchmarks/throughput
repeats=${RUNS:-9}
[[ "$repeats" =~ ^[1-9][0-9]*$ ]] || { echo "benchmarks.sh: RUNS must be a positive whole number, not '$repeats'" >&2; exit 2; }
median() { sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
pps() { grep -o '"particle_steps_per_second": [0-9.e+]*' | awk '{print $2}'; }
echo "| case | particles | contacts per particle | threads | particle-steps/s (median of $repeats) | speed-up over one thread | ns per contact | engine bytes per particle | peak RSS bytes per particle |"
echo "|---|---|---|---|---|---|---|---|---|"
row() {  # dim particles law threads [extra]
  local dim=$1 n=$2 law=$3 threads=$4 extra=${5:-}
  local steps=$(( (dim == 2 ? 20000000 : 6000000) / n ))
  [ "$steps" -lt 20 ] && steps=20
  local runs=() ratios=()
  for k in $(seq "$repeats"); do
    runs+=("$("$tp" --dim "$dim" --particles "$n" --law "$law" --threads "$threads" --steps "$steps" $extra --json)")
    if [ "$threads" -gt 1 ]; then  # the same case on one thread right after: the speed-up as a ratio taken together
      local one
      one=$("$tp" --dim "$dim" --particles "$n" --law "$law" --threads 1 --steps "$steps" $extra --json | pps)
      ratios+=("$(awk -v x="$(echo "${runs[$((k - 1))]}" | pps)" -v y="$one" 'BEGIN {print x / y}')")
    fi
  done
  local speedup=""
  [ "$threads" -gt 1 ] && speedup=$(printf '%s\n' "${ratios[@]}" | median | awk '{printf "%.2fx", $1}')
  local pps ns
  pps=$(printf '%s\n' "${runs[@]}" | pps | median)
  ns=$(printf '%s\n' "${runs[@]}" | grep -o '"ns_per_contact": [0-9.e+]*' | awk '{print $2}' | median)
  local first=${runs[0]}
  local contacts eng rss
  contacts=$(echo "$first" | grep -o '"contacts": [0-9]*' | awk '{print $2}')
  eng=$(echo "$first" | grep -o '"storage_bytes_per_particle": [0-9.]*' | awk '{print $2}')
  rss=$(echo "$first" | grep -o '"bytes_per_particle": [0-9.]*' | awk '{print $2}')
  local label=""
  case "$extra" in
    *shear*) label=" (shear)" ;;
    *float*) label=", float storage" ;;
    *shuffle*sort*) label=", shuffled then sort_spatially()" ;;
    *shuffle*) label=", particles in random order" ;;
    *no-energy*) label=", energy books off" ;;
  esac
  printf '| %dD %s%s | %d | %.2f | %d | %.3g | %s | %.1f | %.0f | %.0f |\n' "$dim" "$law" "$label" "$n" \
    "$(echo "2 * $contacts / $n" | bc -l)" "$threads" "$pps" "$speedup" "$ns" "$eng" "$rss"
}
row 2 1950 frictionless 1
row 2 1950 frictional 1
row 2 1950 frictional 1 --shear
row 2 20000 frictional 1
row 2 20000 frictional 2
row 2 200000 frictionless 1
row 2 200000 frictional 1
row 2 200000 frictional 2
row 2 200000 frictional 1 "--precision float"
row 2 200000 frictional 1 --no-energy
row 2 200000 frictional 1 --shuffle
row 2 200000 frictional 1 "--shuffle --sort"
row 3 12500 frictional 1
row 3 100000 frictional 1
row 3 100000 frictional 2
row 3 100000 frictional 1 "--precision float"
row 3 100000 frictional 1 --no-energy
row 3 100000 frictional 1 --shuffle
row 3 100000 frictional 1 "--shuffle --sort"
