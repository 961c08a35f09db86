#!/usr/bin/env bash
# Usage: bench/speed.sh [--res "128 256"] [--sdfgen PATH] [--openvdb PATH] [--repeat N] [MESH ...]
#
# The speed and memory benchmark behind the README's table. For each mesh and resolution:
#   - `sdfgen bench` (exact distances, sign auto): the seconds of each phase;
#   - `sdfgen bake MESH -o FIELD.npy` under /usr/bin/time -v: the whole process (wall seconds,
#     voxels/s) and its peak resident memory;
#   - OpenVDB's meshToSignedDistanceField on the same grid (bench/openvdb_sdf.cpp, also writing
#     .npy), when its driver is given or built (cmake --build build --target peer_openvdb), and
#     the same-run ratio of whole-process seconds (OpenVDB / sdfgen).
# --repeat N keeps the fastest of N runs of each (the peak memory of sdfgen's last).
#
# Meshes: the ones given, else the Stanford bunny from the shared meshes (../shared/meshes next to
# the repository) when present, else the bundled bunny. The machine is usually shared: compare
# the ratios within one run, and repeat.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sdfgen=$root/build/sdfgen
openvdb=$root/build/bench/peer_openvdb
resolutions="128 256"
repeat=1
meshes=()
while [ $# -gt 0 ]; do
  case $1 in
    --res) resolutions=$2; shift 2 ;;
    --sdfgen) sdfgen=$2; shift 2 ;;
    --openvdb) openvdb=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "speed.sh: unknown option $1" >&2; exit 2 ;;
    *) meshes+=("$1"); shift ;;
  esac
done
[ -x "$sdfgen" ] || { echo "speed.sh: no sdfgen at $sdfgen (build it: cmake --build build --target sdfgen)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "speed.sh: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
[[ $repeat =~ ^[1-9][0-9]*$ ]] || { echo "speed.sh: --repeat must be a positive integer" >&2; exit 2; }
if [ ${#meshes[@]} -eq 0 ]; then
  if [ -f "$root/../shared/meshes/stanford-bunny.obj" ]; then meshes=("$root/../shared/meshes/stanford-bunny.obj")
  else meshes=("$root/assets/bunny.obj"); fi
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# timed OUTVAR COMMAND...: the fastest wall seconds of $repeat runs into OUTVAR, peak RSS (MB) into $rss.
timed() {
  local var=$1 best=
  shift
  for _ in $(seq "$repeat"); do
    /usr/bin/time -f '%e %M' -o "$tmp/time" "$@" >"$tmp/out" 2>"$tmp/err" || { echo "speed.sh: failed: $*" >&2; tail -n 3 "$tmp/err" >&2; return 1; }
    read -r seconds kb <"$tmp/time"
    rss=$((kb / 1024))
    if [ -z "$best" ] || awk -v a="$seconds" -v b="$best" 'BEGIN { exit !(a < b) }'; then best=$seconds; fi
  done
  printf -v "$var" '%s' "$best"
}

printf '%-20s %4s %9s %-20s %6s %6s %8s %6s %6s %7s %10s %7s %8s %7s\n' \
  mesh res triangles sign load tree distance sign save "total s" "voxels/s" "RSS MB" "openvdb" "ratio"
for mesh in "${meshes[@]}"; do
  for res in $resolutions; do
    "$sdfgen" bench "$mesh" --res "$res" --repeat "$repeat" >"$tmp/bench" 2>&1 || { echo "speed.sh: sdfgen bench failed on $mesh" >&2; cat "$tmp/bench" >&2; exit 1; }
    # bench's columns: mesh triangles dims sign load tree distance sign save total voxels/s ...
    row=$(awk 'f { print; exit } /^mesh/ { f = 1 }' "$tmp/bench")
    timed total "$sdfgen" bake "$mesh" --res "$res" -o "$tmp/sdfgen.npy"
    sdfgen_rss=$rss
    samples=$(awk '{ split($3, d, "x"); print d[1] * d[2] * d[3] }' <<<"$row")
    vdb=- ratio=-
    if [ -x "$openvdb" ]; then
      timed vdb "$openvdb" "$mesh" --res "$res" -o "$tmp/openvdb.npy" && ratio=$(awk -v a="$vdb" -v b="$total" 'BEGIN { printf "%.2f", a / b }')
    fi
    awk -v res="$res" -v total="$total" -v samples="$samples" -v rss="$sdfgen_rss" -v vdb="$vdb" -v ratio="$ratio" \
      '{ printf "%-20s %4s %9s %-20s %6s %6s %8s %6s %6s %7s %10.0f %7s %8s %7s\n", $1, res, $2, $4, $5, $6, $7, $8, $9, total, samples / total, rss, vdb, ratio }' <<<"$row"
  done
done
echo "(phases: seconds from sdfgen bench, the sign column includes the mesh check; total: wall seconds of the"
echo " whole 'sdfgen bake -o .npy' process, voxels/s over it; RSS: its peak resident memory; openvdb: wall"
echo " seconds of peer_openvdb on the same grid; ratio = openvdb / sdfgen; $(nproc) cores, best of $repeat)"
