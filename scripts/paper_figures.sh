#!/usr/bin/env bash
# Regenerates the paper reproduction's figures and table (README, examples/biaxial/README.md): runs
# the paper preset (unless RUN names an existing run directory) and the 3D quick preset (unless
# RUN3D does), and renders into docs/figures:
#   sequence_K.png   four frames of the 2D loading on the colour scale of the whole series (Fig. 3);
#   slice_3d.png     a slab through the middle of the 3D box at its last frame, with the force network;
#   the plots of Fig. 4-5 (plot_timeseries).
# Needs a build (scripts/setup.sh run) and, without a display, xvfb-run.
#   scripts/paper_figures.sh            # runs the presets into runs/paper and runs/quick3d (about 6 minutes)
#   RUN=runs/paper RUN3D=runs/quick3d scripts/paper_figures.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
run=${RUN:-runs/paper}
run3d=${RUN3D:-runs/quick3d}
if [ ! -f "$run/timeseries.csv" ]; then
  "$build/examples/biaxial" --preset paper --out "$run" --no-pictures
fi
if [ ! -f "$run3d/timeseries.csv" ]; then
  "$build/examples/biaxial" --preset quick --dim 3 --out "$run3d" --no-pictures
fi
x="xvfb-run -a -s \"-screen 0 1280x1024x24\""
[ -n "${DISPLAY:-}" ] && x=""
out=docs/figures
mkdir -p "$out"
rm -f "$out"/snapshot_*.png "$out"/sequence_*.png
frames=$(grep -c "<DataSet" "$run/vtk/particles.pvd")
for q in 0 1 2 3; do
  k=$(( q * (frames - 1) / 3 ))
  eval $x "$build/viz/render_snapshot" "$run/vtk/particles_$k.vtp" --walls "$run/vtk/walls_$k.vtp" \
    --range-from "$run/vtk/particles.pvd" --size 480x400 -o "$out/sequence_$q.png"
done
frames3d=$(grep -c "<DataSet" "$run3d/vtk/particles.pvd")
last=$(( frames3d - 1 ))
eval $x "$build/viz/render_snapshot" "$run3d/vtk/particles_$last.vtp" --3d --walls "$run3d/vtk/walls_$last.vtp" \
  --contacts "$run3d/vtk/contacts_$last.vtp" --slice y mid 0.004 --range-from "$run3d/vtk/particles.pvd" \
  --size 640x520 -o "$out/slice_3d.png"
eval $x "$build/viz/plot_timeseries" "$run/timeseries.csv" --size 760x460 --out "$out"
rm -f "$out"/*.json
"$build/examples/biaxial_summary" "$run"
