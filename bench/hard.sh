#!/usr/bin/env bash
# Usage: bench/hard.sh [--res "128 256"] [--sdfgen PATH] [--openvdb PATH] [MESH.obj ...]
#
# The speed benchmark behind the README's Benchmarks tables: for each mesh and resolution, one
# `sdfgen bench` run (exact distances, sign auto; phase seconds and voxels/s from its own table)
# under /usr/bin/time -v for the peak resident memory of the whole process, then the same grid by
# OpenVDB's meshToSignedDistanceField (bench/openvdb_sdf.cpp) when its driver is given or built,
# with the same-run ratio of wall-clock seconds (OpenVDB / sdfgen).
#
# Meshes: the ones given, else the shared meshes (../shared/meshes/ next to the repository, when
# present) plus the generated hard ones (bench/hard_meshes.py, written to build/hard-meshes/):
# the Stanford bunny with every 50th triangle removed, a 256x256 heightfield sheet, 100000
# copies of a tetrahedron, the bunny with an exact and a shifted copy of itself, and the bunny
# subdivided twice (1.1 M triangles, bench/subdivide.py).
#
# The machine is usually shared: compare ratios within one run, and repeat.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sdfgen=$root/build/sdfgen
openvdb=$root/build/bench/peer_openvdb
resolutions="128 256"
meshes=()
while [ $# -gt 0 ]; do
  case $1 in
    --res) resolutions=$2; shift 2 ;;
    --sdfgen) sdfgen=$2; shift 2 ;;
    --openvdb) openvdb=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "hard.sh: unknown option $1" >&2; exit 2 ;;
    *) meshes+=("$1"); shift ;;
  esac
done
[ -x "$sdfgen" ] || { echo "hard.sh: no sdfgen at $sdfgen (build it: cmake --build build --target sdfgen)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "hard.sh: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
python=/usr/bin/python3
if [ ${#meshes[@]} -eq 0 ]; then
  shared=$root/../shared/meshes
  bunny=$root/assets/bunny.obj
  if [ -d "$shared" ]; then
    for m in "$shared"/*.obj; do meshes+=("$m"); done
    [ -f "$shared/stanford-bunny.obj" ] && bunny=$shared/stanford-bunny.obj
  fi
  hard=$root/build/hard-meshes
  if [ ! -f "$hard/bunny-1m.obj" ]; then
    "$python" "$root/bench/hard_meshes.py" "$bunny" "$hard"
    "$python" "$root/bench/subdivide.py" "$bunny" "$hard/bunny-1m.obj" 2
  fi
  for m in bunny-holes terrain tetra-copies bunny-overlap bunny-1m; do meshes+=("$hard/$m.obj"); done
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

printf '%-20s %4s %9s %-22s %6s %6s %8s %7s %8s %10s %8s %8s %7s\n' mesh res triangles sign load tree distance sign total voxels/s "RSS MB" openvdb ratio
for mesh in "${meshes[@]}"; do
  for res in $resolutions; do
    # tetra-copies is about copies, not resolution: one small grid.
    [ "$(basename "$mesh")" = tetra-copies.obj ] && [ "$res" != "${resolutions%% *}" ] && continue
    /usr/bin/time -v "$sdfgen" bench "$mesh" --res "$res" >"$tmp/out" 2>"$tmp/time" || { echo "hard.sh: sdfgen failed on $mesh"; tail -n 3 "$tmp/time"; continue; }
    row=$(awk 'f { print; exit } /^mesh/ { f = 1 }' "$tmp/out")
    rss=$(awk '/Maximum resident/ { printf "%.0f", $NF / 1024 }' "$tmp/time")
    vdb=- ratio=-
    if [ -x "$openvdb" ]; then
      start=$(date +%s.%N)
      if "$openvdb" "$mesh" --res "$res" -o "$tmp/vdb.sdf" >/dev/null 2>&1; then
        vdb=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
        total=$(awk '{ print $10 }' <<<"$row")
        ratio=$(awk -v a="$vdb" -v b="$total" 'BEGIN { printf "%.2f", a / b }')
      fi
    fi
    # bench's columns: mesh triangles dims sign load tree distance sign save total voxels/s ...
    awk -v res="$res" -v rss="$rss" -v vdb="$vdb" -v ratio="$ratio" \
      '{ printf "%-20s %4s %9s %-22s %6s %6s %8s %7s %8s %10s %8s %8s %7s\n", $1, res, $2, $4, $5, $6, $7, $8, $10, $11, rss, vdb, ratio }' <<<"$row"
  done
done
echo "(seconds per phase from sdfgen bench; the sign column includes topology and the mesh check;"
echo " RSS: peak resident memory of the whole bench process; openvdb: wall-clock seconds of"
echo " peer_openvdb on the same grid, ratio = openvdb / sdfgen total; $(nproc) cores)"
