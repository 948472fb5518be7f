#!/usr/bin/env bash
# The loading rate as a speed-accuracy trade: one prepared packing loaded at T = 1, 2, 4 and 8 s
# (T of Eq. 17; the motion lasts T/2), and for each the roughness of sigma_22 (run.json "quality")
# and the largest gaps to the slowest run of the smoothed stress ratio (s_zz - s_xx)/(s_zz + s_xx),
# deviatoric fabric and C_n_zzzz / k on eps_zz 0.02-0.18 (each column averaged over +-0.005 of
# strain, then interpolated onto a grid of 0.001), with the wall seconds of each run.
# About 15 minutes for the paper preset on two cores (two runs at a time).
#   scripts/rate_convergence.sh                   # the paper preset, seed 1
#   PRESET=quick PERIODS="0.1 0.2 0.4 0.8" scripts/rate_convergence.sh
#   PREPARED=runs/paper/prepared.state scripts/rate_convergence.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
preset=${PRESET:-paper}
periods=(${PERIODS:-1 2 4 8})
out=${OUT:-runs/rate_$preset}
mkdir -p "$out"
prepared=${PREPARED:-}
if [ -z "$prepared" ]; then  # the preset's preparation only: stop at its first row
  "$build/examples/biaxial" --preset "$preset" --out "$out/prepare" --overwrite --no-pictures --quiet --vtk-every 0 --stop-after-rows 1 || true
  prepared=$out/prepare/prepared.state
fi
load() {
  rm -rf "$out/T$1"
  "$build/examples/biaxial" --preset "$preset" --from-prepared "$prepared" --period "$1" --out "$out/T$1" --no-pictures \
    --quiet --vtk-every 0 > /dev/null
}
# Slowest first, paired with the fastest, so that the two cores stay busy.
for ((lo = 0, hi = ${#periods[@]} - 1; lo <= hi; ++lo, --hi)); do
  if [ "$lo" -lt "$hi" ]; then load "${periods[$hi]}" & load "${periods[$lo]}"; wait; else load "${periods[$lo]}"; fi
done
/usr/bin/python3 - "$out" "${periods[@]}" <<'EOF'
import csv, json, sys
out, periods = sys.argv[1], sys.argv[2:]
def series(T):
    rows = [r for r in csv.reader(open(f"{out}/T{T}/timeseries.csv")) if r and not r[0].startswith("#")]
    names = rows[0]
    col = {n: [float(r[i]) for r in rows[1:]] for i, n in enumerate(names)}
    run = json.load(open(f"{out}/T{T}/run.json"))
    dim = run["parameters"]["dim"]; z = f"{dim}{dim}"; k = run["parameters"]["k_N_m"]
    final = run["parameters"]["final_strain"]
    motion = [i for i, e in enumerate(col["strain_" + z]) if e < final - 1e-12]
    eps = [col["strain_" + z][i] for i in motion]
    quantities = {
        "stress ratio": [(col["sigma_" + z][i] - col["sigma_11"][i]) / (col["sigma_" + z][i] + col["sigma_11"][i]) for i in motion],
        "deviatoric fabric": [col["deviatoric_fabric"][i] for i in motion],
        "C_n_zzzz / k": [col["C_n_" + z + z][i] / k for i in motion],
    }
    def smoothed_on_grid(values):
        grid, result = [0.02 + 0.001 * g for g in range(161)], []
        for e in grid:
            window = [v for x, v in zip(eps, values) if abs(x - e) <= 0.005]
            result.append(sum(window) / len(window))
        return result
    return {q: smoothed_on_grid(v) for q, v in quantities.items()}, run
data = {T: series(T) for T in periods}
slow = max(periods, key=float)
print("| T (s) | roughness sigma_zz | largest gap to T = %s s: stress ratio | deviatoric fabric | C_n_zzzz / k | wall seconds |" % slow)
print("|---|---|---|---|---|---|")
for T in sorted(periods, key=float):
    smooth, run = data[T]
    gaps = [max(abs(a - b) for a, b in zip(smooth[q], data[slow][0][q])) for q in ("stress ratio", "deviatoric fabric", "C_n_zzzz / k")]
    print("| %s | %.3f | %.3f | %.3f | %.3f | %.0f |" % (T, run["quality"]["roughness_sigma_zz"], *gaps, run["timing"]["wall_seconds"]))
EOF
