#!/usr/bin/env bash
# Regenerates the paper reproduction's figures and table (README, examples/biaxial/README.md): runs the paper preset (unless RUN names an
# existing run directory) and renders into docs/figures. Needs a build (scripts/setup.sh run) and,
# without a display, xvfb-run.
#   scripts/paper_figures.sh            # runs the paper preset into runs/paper (about 3 minutes)
#   RUN=runs/paper scripts/paper_figures.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
run=${RUN:-runs/paper}
if [ ! -f "$run/timeseries.csv" ]; then
  "$build/examples/biaxial" --preset paper --out "$run" --no-pictures
fi
x="xvfb-run -a -s \"-screen 0 1280x1024x24\""
[ -n "${DISPLAY:-}" ] && x=""
out=docs/figures
mkdir -p "$out"
frames=$(grep -c "<DataSet" "$run/vtk/particles.pvd")
for k in 0 $(( (frames - 1) / 2 )) $(( frames - 1 )); do
  eval $x "$build/viz/render_snapshot" "$run/vtk/particles_$k.vtp" --walls "$run/vtk/walls_$k.vtp" \
    --size 640x520 -o "$out/snapshot_$k.png"
done
eval $x "$build/viz/plot_timeseries" "$run/timeseries.csv" --size 760x460 --out "$out"
rm -f "$out"/*.json
"$build/examples/biaxial_summary" "$run"
