#!/usr/bin/env bash
# The biaxial program over MPI ranks against the serial one, on whole runs: for each seed the
# serial program prepares and loads a packing, and biaxial_mpi loads the same prepared packing on
# RANKS ranks. Where the ranks keep the serial bits (docs/mpi.md) every difference is 0; where they
# agree to round-off only, it grows by chaos over the loading and the two runs' curves part. The
# table compares each key figure's serial-vs-ranks difference with its seed-to-seed scatter
# (the standard deviation over the seeds of the serial runs), and gives the mean signed difference
# with its standard error, which a bias of the ranks would move off zero. Prints Markdown
# (docs/mpi.md).
#   scripts/mpi_vs_serial.sh                      # 2D quick preset, seeds 1-6, 2 ranks
#   DIM=3 SEEDS="1 2 3 4 5 6" RANKS=3 scripts/mpi_vs_serial.sh
#   BASELINE_RANKS=3 scripts/mpi_vs_serial.sh    # and 3 ranks against 2: how far round-off alone takes runs apart
#   ARGS="--particles 500" DIM=3 scripts/mpi_vs_serial.sh   # options of the serial run that prepares each packing
# Needs build/examples/biaxial, biaxial_mpi and biaxial_summary (scripts/setup.sh test).
set -euo pipefail
cd "$(dirname "$0")/.."
dim=${DIM:-2} seeds=${SEEDS:-"1 2 3 4 5 6"} ranks=${RANKS:-2} preset=${PRESET:-quick}
read -r -a args <<<"${ARGS:-}"
build=${BUILD_DIR:-build}
for p in biaxial biaxial_mpi biaxial_summary; do
  [ -x "$build/examples/$p" ] || { echo "mpi_vs_serial.sh: no $build/examples/$p; build first (scripts/setup.sh test)" >&2; exit 1; }
done
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
[ -n "${KEEP:-}" ] && trap - EXIT && echo "keeping $work" >&2
# The figures of biaxial_summary's table compared: "label|row text|field" (fields of the value
# column split at ', ' or '; ').
figures() {  # figures RUN_DIR: prints "name value" lines
  "$build/examples/biaxial_summary" "$1" | awk -F'|' '
    /peak stress ratio/ { split($3, a, " "); print "peak_stress_ratio", a[1] }
    /maximum deviatoric fabric/ { split($3, a, " "); print "max_deviatoric_fabric", a[1] }
    /late stress ratio, deviatoric fabric/ { n = split($3, a, ", "); print "late_stress_ratio", a[1]; print "late_deviatoric_fabric", a[2]; print "late_Cn_zzzz_over_Cn_1111", a[3] }
    /late coordination, volume fraction/ { n = split($3, a, ", "); print "late_coordination", a[1]; print "late_volume_fraction", a[2] }'
}
for s in $seeds; do
  "$build/examples/biaxial" --dim "$dim" --preset "$preset" --seed "$s" "${args[@]}" --vtk-every 0 --no-pictures --quiet \
    --out "$work/serial_$s" >/dev/null
  figures "$work/serial_$s" | sed "s/^/serial $s /"
  for r in $ranks ${BASELINE_RANKS:-}; do
    mpirun -np "$r" --oversubscribe "$build/examples/biaxial_mpi" --dim "$dim" --preset "$preset" --vtk-every 0 --no-pictures --quiet \
      --from-prepared "$work/serial_$s/prepared.state" --out "$work/ranks${r}_$s" >/dev/null
    figures "$work/ranks${r}_$s" | sed "s/^/ranks$r $s /"
  done
done >"$work/figures.txt"
table() {  # table A B: the figures of A, their scatter over the seeds, and A - B
  echo "| figure | $1, mean over seeds | seed-to-seed scatter (std) | $1 - $2: mean of abs | largest abs | largest abs over scatter | mean, +- its standard error |"
  echo "|---|---|---|---|---|---|---|"
  awk -v A="$1" -v B="$2" '
    { v[$1, $2, $3] = $4; names[$3] = 1; seedset[$2] = 1 }
    END {
      order = "peak_stress_ratio max_deviatoric_fabric late_stress_ratio late_deviatoric_fabric late_Cn_zzzz_over_Cn_1111 late_coordination late_volume_fraction"
      k = split(order, list, " ")
      for (i = 1; i <= k; ++i) {
        f = list[i]; if (!(f in names)) continue
        n = 0; sum = 0; sq = 0; d = 0; dmax = 0; ds = 0; dsq = 0
        for (s in seedset) {
          x = v[A, s, f]; y = v[B, s, f]; n++; sum += x; sq += x * x
          ds += x - y; dsq += (x - y) * (x - y); a = x - y; if (a < 0) a = -a; d += a; if (a > dmax) dmax = a
        }
        mean = sum / n; sd = (n > 1) ? sqrt((sq - n * mean * mean) / (n - 1)) : 0
        ratio = (sd > 0) ? dmax / sd : 0
        dm = ds / n; se = (n > 1) ? sqrt((dsq - n * dm * dm) / (n - 1) / n) : 0
        printf "| %s | %.4g | %.3g | %.3g | %.3g | %.2f | %+.3g +- %.3g |\n", f, mean, sd, d / n, dmax, ratio, dm, se
      }
    }' "$work/figures.txt"
}
echo "${dim}D $preset preset${ARGS:+ ($ARGS)}, seeds $seeds: the serial program, and biaxial_mpi on $ranks ranks from the same prepared packing."
echo
table serial "ranks$ranks"
if [ -n "${BASELINE_RANKS:-}" ]; then
  echo
  echo "Baseline, round-off alone: biaxial_mpi on $BASELINE_RANKS ranks against $ranks, from the same packings."
  echo
  table "ranks$BASELINE_RANKS" "ranks$ranks"
fi
