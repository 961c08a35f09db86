#!/usr/bin/env bash
# Usage: bench/hard.sh [--res "128 256"] [--sdfgen PATH] [--before PATH] [--openvdb PATH]
#                      [--timeout S] [--bunny PATH] [MESH.obj ...]
#
# The benchmark behind the README's "Hard meshes" table: for each mesh and resolution, one
# `sdfgen bench` run (exact distances, sign auto; phase seconds and voxels/s from its own table)
# under /usr/bin/time -v for the peak resident memory of the whole process; then, when given,
# the same run by a second sdfgen binary (--before, e.g. a build of an older commit) and the same
# grid by OpenVDB's meshToSignedDistanceField (bench/openvdb_sdf.cpp, built on demand as
# peer_openvdb), with the same-run ratios of wall-clock seconds (before / sdfgen, openvdb / sdfgen).
# A run past --timeout seconds (default 120) is cut and shown as ">S".
#
# Meshes: the ones given, else the Stanford bunny (../shared/meshes/ next to the repository, when
# present, or --bunny; else assets/bunny.obj) and the generated hard ones (bench/hard_meshes.py, written to
# build/hard-meshes/): the bunny with every 50th triangle removed, a 256x256 heightfield sheet,
# 100000 copies of a tetrahedron, the bunny with an exact and a shifted copy of itself, and the
# bunny subdivided twice (bench/subdivide.py; 1.1 M triangles from the Stanford bunny).
#
# The machine is usually shared: compare ratios within one run, and repeat.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sdfgen=$root/build/sdfgen
before=
openvdb=$root/build/bench/peer_openvdb
resolutions="128 256"
limit=120
bunny=
meshes=()
while [ $# -gt 0 ]; do
  case $1 in
    --res) resolutions=$2; shift 2 ;;
    --sdfgen) sdfgen=$2; shift 2 ;;
    --before) before=$2; shift 2 ;;
    --openvdb) openvdb=$2; shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --bunny) bunny=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "hard.sh: unknown option $1" >&2; exit 2 ;;
    *) meshes+=("$1"); shift ;;
  esac
done
[ -x "$sdfgen" ] || { echo "hard.sh: no sdfgen at $sdfgen (build it: cmake --build build --target sdfgen)" >&2; exit 1; }
[ -z "$before" ] || [ -x "$before" ] || { echo "hard.sh: no sdfgen at $before (--before)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "hard.sh: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
python=/usr/bin/python3
if [ ${#meshes[@]} -eq 0 ]; then
  [ -z "$bunny" ] && [ -f "$root/../shared/meshes/stanford-bunny.obj" ] && bunny=$root/../shared/meshes/stanford-bunny.obj
  [ -z "$bunny" ] && bunny=$root/assets/bunny.obj
  hard=$root/build/hard-meshes
  if [ ! -f "$hard/bunny-1m.obj" ]; then
    "$python" "$root/bench/hard_meshes.py" "$bunny" "$hard"
    "$python" "$root/bench/subdivide.py" "$bunny" "$hard/bunny-1m.obj" 2
  fi
  meshes+=("$bunny")
  for m in bunny-holes terrain tetra-copies bunny-overlap bunny-1m; do meshes+=("$hard/$m.obj"); done
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Wall-clock seconds of a command (">limit" when cut), its output in $tmp/out and $tmp/time.
timed() {
  local start end
  start=$(date +%s.%N)
  local rc=0
  timeout "$limit" /usr/bin/time -v "$@" >"$tmp/out" 2>"$tmp/time" || rc=$?
  end=$(date +%s.%N)
  case $rc in
    0) awk -v s="$start" -v e="$end" 'BEGIN { printf "%.2f", e - s }' ;;
    124) echo ">$limit" ;;
    *) echo "failed" ;;
  esac
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "failed") printf "-"; else if (a ~ /^>/) printf ">%.1f", substr(a, 2) / b; else printf "%.2f", a / b }'; }

printf '%-18s %4s %9s %-17s %6s %6s %8s %7s %7s %10s %6s %8s %7s %8s %7s\n' \
  mesh res triangles sign load tree distance sign total voxels/s "RSS MB" before ratio openvdb ratio
for mesh in "${meshes[@]}"; do
  for res in $resolutions; do
    # tetra-copies is about copies, not resolution: one small grid.
    [ "$(basename "$mesh")" = tetra-copies.obj ] && [ "$res" != "${resolutions%% *}" ] && continue
    wall=$(timed "$sdfgen" bench "$mesh" --res "$res")
    case $wall in
      '>'*) echo "hard.sh: sdfgen ran past ${limit}s on $mesh"; continue ;;
      failed) echo "hard.sh: sdfgen failed on $mesh:"; tail -n 3 "$tmp/time"; continue ;;
    esac
    row=$(awk 'f { print; exit } /^mesh/ { f = 1 }' "$tmp/out")
    rss=$(awk '/Maximum resident/ { printf "%.0f", $NF / 1024 }' "$tmp/time")
    old=- oldRatio=- vdb=- vdbRatio=-
    if [ -n "$before" ]; then
      old=$(timed "$before" bench "$mesh" --res "$res")
      oldRatio=$(ratio "$old" "$wall")
    fi
    if [ -x "$openvdb" ]; then
      vdb=$(timed "$openvdb" "$mesh" --res "$res" -o "$tmp/vdb.sdf")
      vdbRatio=$(ratio "$vdb" "$wall")
    fi
    # bench's columns: mesh triangles dims sign load tree distance sign save total voxels/s ...
    awk -v res="$res" -v rss="$rss" -v old="$old" -v oldRatio="$oldRatio" -v vdb="$vdb" -v vdbRatio="$vdbRatio" \
      '{ printf "%-18s %4s %9s %-17s %6s %6s %8s %7s %7s %10s %6s %8s %7s %8s %7s\n", $1, res, $2, $4, $5, $6, $7, $8, $10, $11, rss, old, oldRatio, vdb, vdbRatio }' <<<"$row"
  done
done
echo "(seconds per phase from sdfgen bench, the sign phase including topology and the mesh check; RSS: peak"
echo " resident memory of the whole bench process; before and openvdb: wall-clock seconds of the other binary on"
echo " the same grid, each ratio = its seconds / sdfgen's wall-clock seconds; $(nproc) cores)"
