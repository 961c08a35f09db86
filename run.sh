#!/usr/bin/env bash
# Builds sdfgen (installing missing Debian packages first) and opens the viewer on the bundled bunny.
# Without a display (no DISPLAY or WAYLAND_DISPLAY) it does the headless equivalent instead: bakes
# the bunny and renders a PNG of each view into out/ with `sdfgen render`.
# Extra arguments go to `sdfgen bake` in the headless case, e.g. ./run.sh --res 128
set -euo pipefail
cd "$(dirname "$0")"
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -- sdfgen
if [ -n "${DISPLAY:-}" ] || [ -n "${WAYLAND_DISPLAY:-}" ]; then
  exec ./build/sdfgen view assets/bunny.obj
fi
echo "run.sh: no display (DISPLAY and WAYLAND_DISPLAY are unset), so no viewer window: rendering PNGs of each view headless instead"
mkdir -p out
./build/sdfgen bake assets/bunny.obj -o out/bunny.sdf "$@"
for view in grid mesh wire volume raymarch slice; do
  ./build/sdfgen render assets/bunny.obj --sdf out/bunny.sdf --view "grid,$view" --size 1280x720 -o "out/bunny-$view.png"
done
echo "run.sh: wrote $(ls out/bunny-*.png | tr '\n' ' ')"
