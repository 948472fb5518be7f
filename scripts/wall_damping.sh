#!/usr/bin/env bash
# Regenerates the README's side-wall damper table: the first 200 rows of the paper preset's
# loading under five side-wall dampers, all from one prepared packing, and for each the
# roughness of sigma_wall_11 (rms about its centred 25-row running mean, over its mean) and its
# mean. Needs a build; about 2 minutes on one core.
#   scripts/wall_damping.sh                 # prepares the paper packing into runs/wall_damping
#   PREPARED=runs/paper/prepared.state scripts/wall_damping.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
out=${OUT:-runs/wall_damping}
mkdir -p "$out"
prepared=${PREPARED:-}
if [ -z "$prepared" ]; then  # the paper preset's preparation only: stop at its first row
  "$build/examples/biaxial" --preset paper --out "$out/prepare" --no-pictures --quiet --vtk-every 0 --stop-after-rows 1 || true
  prepared=$out/prepare/prepared.state
fi
echo "| side wall damper | roughness | mean sigma_wall_11 (N/m, target 20) |"
echo "|---|---|---|"
case_row() {  # label, then biaxial options
  local label=$1; shift
  local dir="$out/$(echo "$label" | tr -c 'a-zA-Z0-9.\n' '_')"
  "$build/examples/biaxial" --preset paper --from-prepared "$prepared" --out "$dir" --no-pictures --quiet \
    --vtk-every 0 --stop-after-rows 200 "$@" > /dev/null || true  # stops abruptly (exit 3) by design
  awk -F, -v label="$label" '
    /^#/ { next }
    !col { for (i = 1; i <= NF; ++i) if ($i == "sigma_wall_11") col = i; next }
    { s[n++] = $col }
    END {
      w = 12; sum = 0; for (i = 0; i < n; ++i) sum += s[i]; mean = sum / n
      for (i = w; i < n - w; ++i) { m = 0; for (k = i - w; k <= i + w; ++k) m += s[k]; m /= 2 * w + 1
                                    d = s[i] - m; sq += d * d; count++ }
      printf "| %s | %.3f | %.1f |\n", label, sqrt(sq / count) / mean, mean
    }' "$dir/timeseries.csv.partial"
}
case_row "Eq. 18, gamma_w = 0.63 kg/s (default)"
case_row "Eq. 18, gamma_w = 6.3 kg/s" --wall-damping 6.3
case_row "Eq. 18, gamma_w = 20 kg/s" --wall-damping 20
case_row "--wall-follow-time 0.01, gamma_w = 10 kg/s" --wall-damping 10 --wall-follow-time 0.01
case_row "--wall-follow-time 0.005, gamma_w = 20 kg/s" --wall-damping 20 --wall-follow-time 0.005
