#!/usr/bin/env bash
# Scaling of the default bake (exact + auto) with grid resolution and triangle count.
# Usage: bench/scaling.sh   (uses the bundled bunny, ../shared/meshes when present, and a
# 4x-subdivided Stanford bunny made on the fly)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" "$root/build" -DCMAKE_BUILD_TYPE=Release -- sdfgen >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
meshes=("$root/assets/bunny.obj")
for m in suzanne cow fandisk rocker-arm stanford-bunny; do
  [ -f "$root/../shared/meshes/$m.obj" ] && meshes+=("$root/../shared/meshes/$m.obj")
done
if [ -f "$root/../shared/meshes/stanford-bunny.obj" ]; then
  /usr/bin/python3 "$root/bench/subdivide.py" "$root/../shared/meshes/stanford-bunny.obj" "$work/stanford-bunny-x4.obj" 1
  meshes+=("$work/stanford-bunny-x4.obj")
fi
echo "| mesh | triangles | res 64 | res 128 | res 256 |"
echo "|---|---:|---:|---:|---:|"
for mesh in "${meshes[@]}"; do
  row="| $(basename "$mesh" .obj)"
  for res in 64 128 256; do
    line=$("$root/build/sdfgen" bench "$mesh" --res "$res" | sed -n 3p)
    [ "$res" = 64 ] && row+=" | $(awk '{print $2}' <<<"$line")"
    row+=" | $(awk '{print $10}' <<<"$line") s"
  done
  echo "$row |"
done
echo
echo "Whole process (load + tree + distances + signs + save) in seconds, exact distances with sign auto."
