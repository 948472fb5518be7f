#!/usr/bin/env bash
# The oblique impacts of docs/oblique-impacts.md run by LAMMPS (gran/hooke/history, the same law
# without dashpots, Debian's lammps package, installed if missing): the same spheres, speeds,
# impact parameters, spin and entry phases, each time step against LAMMPS's own run at t_c/12800.
# Prints a Markdown page (docs/oblique-impacts-lammps.md is its output).
#   scripts/oblique_impacts_lammps.sh > docs/oblique-impacts-lammps.md   (PHASES=16: ~10 minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
phases=${PHASES:-16}
[[ "$phases" =~ ^[1-9][0-9]*$ ]] || { echo "oblique_impacts_lammps.sh: PHASES must be a positive whole number, not '$phases'" >&2; exit 2; }
# shellcheck source=scripts/lammps/environment.sh
source scripts/lammps/environment.sh
deck=scripts/lammps/oblique_impact.in
a=1e-3 m=8.377580409572781e-06 k=1e5
tc=$(awk -v m=$m -v k=$k 'BEGIN { printf "%.17g", 3.141592653589793 / sqrt(k / (m / 2)) }')

# impact DIM B MU STEPS_PER_TC PHASE -> "wx wy wz dvy dvz"
impact() {
  local dim=$1 b=$2 mu=$3 frac=$4 phase=$5
  local args
  args=$(awk -v a=$a -v b="$b" -v tc="$tc" -v frac="$frac" -v phase="$phase" -v dim="$dim" 'BEGIN {
    dt = tc / frac; meet = (4 - phase) * dt
    x0 = -sqrt(4 * a * a - b * b) - 0.5 * meet
    if (dim == 2) { y0 = b; z0 = 0 } else { y0 = b * sqrt(3) / 2; z0 = b / 2 }
    printf "-var x0 %.17g -var y0 %.17g -var z0 %.17g -var dt %.17g -var steps %d", x0, y0, z0, dt, int((meet + 2 * tc) / dt) + 2 }')
  # shellcheck disable=SC2086  # args holds several options
  lmp -log none -nocite -var dim "$dim" -var mu "$mu" -var w0 300 $args -in "$deck" | awk '/^RESULT/ { print $2, $3, $4, $5, $6 }'
}

cases=("0.3e-3 0.5" "0.8e-3 0.5" "1.5e-3 0.5" "1.9e-3 0.5" "0.8e-3 0.05")
steps=(20 50 100 200 400)
help=$(lmp -h 2>/dev/null || true)
version=$(awk -F' - ' '/^Large-scale Atomic/ { print $2 ($3 ? ", " $3 : ""); exit }' <<<"$help")
echo "# Oblique impacts in LAMMPS"
echo
echo "Made by \`scripts/oblique_impacts_lammps.sh > docs/oblique-impacts-lammps.md\` (PHASES=$phases; Debian's LAMMPS"
echo "${version:-}, \`pair_style gran/hooke/history 1e5 2e4 0 0 mu 0\`, \`fix nve/sphere\`, on $(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo))."
echo "The impacts of [oblique-impacts.md](oblique-impacts.md): the same spheres, impact parameters, spin and $phases entry"
echo "phases; errors relative to LAMMPS's own run at t_c/12800. LAMMPS evaluates the forces with the"
echo "half-step velocity, advances the spring by it and starts a new contact's spring with a whole step."
for dim in 2 3; do
  echo
  echo "## ${dim}D"
  echo
  echo "| b (mm), mu | error | $(printf 't_c/%s | ' "${steps[@]}")order |"
  echo "|---|---|$(printf -- '---|%.0s' "${steps[@]}")---|"
  for c in "${cases[@]}"; do
    read -r b mu <<<"$c"
    refs=()
    for p in $(seq 0 $((phases - 1))); do
      refs+=("$(impact "$dim" "$b" "$mu" 12800 "$(awk -v p="$p" -v n="$phases" 'BEGIN { print (p + 0.5) / n }')")")
    done
    spin_worst=() spin_rms=() vt_worst=()
    for frac in "${steps[@]}"; do
      stats=$(for p in $(seq 0 $((phases - 1))); do
        echo "${refs[$p]} $(impact "$dim" "$b" "$mu" "$frac" "$(awk -v p="$p" -v n="$phases" 'BEGIN { print (p + 0.5) / n }')")"
      done | awk '{
        ds = sqrt(($6-$1)^2 + ($7-$2)^2 + ($8-$3)^2) / sqrt($1^2 + $2^2 + $3^2)
        dv = sqrt(($9-$4)^2 + ($10-$5)^2) / sqrt($4^2 + $5^2)
        if (ds > sw) sw = ds; if (dv > vw) vw = dv; ss += ds * ds; n++
      } END { printf "%.1e %.1e %.1e", sw, sqrt(ss / n), vw }')
      read -r sw sr vw <<<"$stats"
      spin_worst+=("$sw") spin_rms+=("$sr") vt_worst+=("$vw")
    done
    row() {
      local label=$1; shift
      local values=("$@")
      local order
      order=$(awk -v e0="${values[0]}" -v e1="${values[-1]}" -v s0="${steps[0]}" -v s1="${steps[-1]}" 'BEGIN { printf "%.1f", log(e0 / e1) / log(s1 / s0) }')
      echo "| $(awk -v b="$b" 'BEGIN { print b * 1e3 }'), $mu | $label | $(printf '%s | ' "${values[@]}")$order |"
    }
    row "spin, worst" "${spin_worst[@]}"
    row "spin, rms" "${spin_rms[@]}"
    row "v_t, worst" "${vt_worst[@]}"
  done
done
