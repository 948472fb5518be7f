#!/usr/bin/env bash
# Regenerates the table of docs/loading-damping.md: the paper preset loaded from one
# prepared packing under several damping policies, and for each the quality figures of its
# run.json (examples/biaxial/quality.hpp): roughness of sigma_22, the fixed and the controlled
# side wall's mean push, the controlled wall's rms deviation from p, the median gap between the
# inner-box stress and the wall stress per axis, and the damping's energy over the walls' work.
# Needs a build; about 5 minutes on two cores (two runs at a time).
#   scripts/loading_damping.sh                       # prepares the paper packing (seed 1)
#   PREPARED=runs/paper/prepared.state scripts/loading_damping.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
out=${OUT:-runs/loading_damping}
mkdir -p "$out"
prepared=${PREPARED:-}
if [ -z "$prepared" ]; then  # the paper preset's preparation only: stop at its first row
  "$build/examples/biaxial" --preset paper --out "$out/prepare" --overwrite --no-pictures --quiet --vtk-every 0 --stop-after-rows 1 || true
  prepared=$out/prepare/prepared.state
fi
load() {  # label, then biaxial options
  local label=$1; shift
  local dir="$out/$(echo "$label" | tr -c 'a-zA-Z0-9.\n' '_')"
  rm -rf "$dir"
  "$build/examples/biaxial" --preset paper --from-prepared "$prepared" --out "$dir" --no-pictures --quiet --vtk-every 0 "$@" > /dev/null
}
load "Eq. 30 (lab) 1e-4 kg/s, Eq. 18 gamma_w 0.63 kg/s" --damping lab --gamma-b 1e-4 --wall-damping 0.63 &
load "Eq. 30 (lab) 5e-2 kg/s, gamma_w 0" --damping lab --gamma-b 5e-2 --wall-damping 0
wait
load "affine 5e-2 kg/s, gamma_w 0.63 kg/s" --damping affine --gamma-b 5e-2 --wall-damping 0.63 &
load "affine 5e-2 kg/s, gamma_w 0 (default)" --damping affine --gamma-b 5e-2 --wall-damping 0
wait
load "affine 2e-1 kg/s, gamma_w 0" --damping affine --gamma-b 2e-1 --wall-damping 0 &
load "local alpha = 0.2, gamma_w 0" --damping local --local-damping 0.2 --wall-damping 0
wait
labels=("Eq. 30 (lab) 1e-4 kg/s, Eq. 18 gamma_w 0.63 kg/s" "Eq. 30 (lab) 5e-2 kg/s, gamma_w 0"
        "affine 5e-2 kg/s, gamma_w 0.63 kg/s" "affine 5e-2 kg/s, gamma_w 0 (default)"
        "affine 2e-1 kg/s, gamma_w 0" "local alpha = 0.2, gamma_w 0")
echo "| damping while loading | roughness sigma_22 | fixed / controlled side wall (N/m, p = 20) | controlled wall rms off p | inner vs wall, axis 1 / 2 | damping / wall work | wall seconds |"
echo "|---|---|---|---|---|---|---|"
for label in "${labels[@]}"; do
  dir="$out/$(echo "$label" | tr -c 'a-zA-Z0-9.\n' '_')"
  /usr/bin/python3 - "$label" "$dir/run.json" <<'EOF'
import json, sys
label, path = sys.argv[1], sys.argv[2]
run = json.load(open(path))
q = run["quality"]
print("| %s | %.3f | %.2f / %.2f | %.1f%% | %+.1f%% / %+.1f%% | %.0f%% | %.0f |" % (
    label, q["roughness_sigma_zz"], q["fixed_side_wall_mean"][0], q["controlled_side_wall_mean"][0],
    100 * q["controlled_side_wall_rms_deviation_over_p"][0], 100 * q["inner_minus_wall_stress_over_wall_stress_median"][0],
    100 * q["inner_minus_wall_stress_over_wall_stress_median"][1], 100 * q["damping_energy_over_wall_work"],
    run["timing"]["wall_seconds"]))
EOF
done
