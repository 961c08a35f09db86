#!/usr/bin/env bash
# Usage: bench/speed.sh [--res "128 256"] [--hard] [--sdfgen PATH] [--before PATH] [--openvdb PATH]
#                       [--repeat N] [--timeout S] [--bunny PATH] [MESH.obj ...]
#
# The speed and memory benchmark behind the tables of docs/benchmarks.md. For each mesh and resolution:
#   - `sdfgen bench` (exact distances, sign auto): the seconds of each phase;
#   - `sdfgen bake MESH -o FIELD.npy` under /usr/bin/time: the whole process (wall seconds,
#     voxels/s) and its peak resident memory;
#   - with --before PATH, the same whole bake by a second sdfgen binary (e.g. a build of an older
#     commit), and the same-run ratio before / sdfgen;
#   - OpenVDB's meshToSignedDistanceField on the same grid (bench/openvdb_sdf.cpp, also writing
#     .npy), when its driver is given or built (cmake --build build --target peer_openvdb), and
#     the same-run ratio openvdb / sdfgen.
# --repeat N keeps the fastest of N runs of each (the peak memory of sdfgen's last). A run past
# --timeout seconds (default 120) is cut and shown as ">S".
#
# Meshes: the ones given, else the Stanford bunny (../shared/meshes/ next to the repository when
# present, or --bunny PATH; else assets/bunny.obj). --hard adds the generated hard meshes
# (bench/hard_meshes.py, written once to build/hard-meshes/): the bunny with every 50th triangle
# removed, a 256x256 heightfield sheet, 100000 copies of a tetrahedron (at the first resolution
# only: it is about copies, not resolution), the bunny with an exact and a shifted copy of itself,
# and the bunny subdivided twice (bench/subdivide.py; 1.1 M triangles from the Stanford bunny).
#
# The machine is usually shared: compare the ratios within one run, and repeat.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sdfgen=$root/build/sdfgen
before=
openvdb=$root/build/bench/peer_openvdb
resolutions="128 256"
repeat=1
limit=120
hard=0
bunny=
meshes=()
while [ $# -gt 0 ]; do
  case $1 in
    --res) resolutions=$2; shift 2 ;;
    --hard) hard=1; shift ;;
    --sdfgen) sdfgen=$2; shift 2 ;;
    --before) before=$2; shift 2 ;;
    --openvdb) openvdb=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --bunny) bunny=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "speed.sh: unknown option $1" >&2; exit 2 ;;
    *) meshes+=("$1"); shift ;;
  esac
done
[ -x "$sdfgen" ] || { echo "speed.sh: no sdfgen at $sdfgen (build it: cmake --build build --target sdfgen)" >&2; exit 1; }
[ -z "$before" ] || [ -x "$before" ] || { echo "speed.sh: no sdfgen at $before (--before)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "speed.sh: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
[[ $repeat =~ ^[1-9][0-9]*$ ]] || { echo "speed.sh: --repeat must be a positive integer" >&2; exit 2; }
[[ $limit =~ ^[1-9][0-9]*$ ]] || { echo "speed.sh: --timeout must be a positive number of seconds" >&2; exit 2; }
if [ ${#meshes[@]} -eq 0 ]; then
  [ -z "$bunny" ] && [ -f "$root/../shared/meshes/stanford-bunny.obj" ] && bunny=$root/../shared/meshes/stanford-bunny.obj
  [ -z "$bunny" ] && bunny=$root/assets/bunny.obj
  meshes=("$bunny")
  if [ "$hard" = 1 ]; then
    generated=$root/build/hard-meshes
    if [ ! -f "$generated/bunny-1m.obj" ]; then
      /usr/bin/python3 "$root/bench/hard_meshes.py" "$bunny" "$generated"
      /usr/bin/python3 "$root/bench/subdivide.py" "$bunny" "$generated/bunny-1m.obj" 2
    fi
    for m in bunny-holes terrain tetra-copies bunny-overlap bunny-1m; do meshes+=("$generated/$m.obj"); done
  fi
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# timed OUTVAR COMMAND...: the fastest wall seconds of $repeat runs into OUTVAR (">limit" when cut,
# "failed" when it failed), peak RSS (MB) of the last into $rss.
timed() {
  local var=$1 best= rc seconds kb
  shift
  rss=-
  for _ in $(seq "$repeat"); do
    rc=0
    timeout "$limit" /usr/bin/time -f '%e %M' -o "$tmp/time" "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
    if [ "$rc" = 124 ]; then best=">$limit"; break; fi
    if [ "$rc" != 0 ]; then
      echo "speed.sh: failed: $*" >&2
      tail -n 3 "$tmp/err" >&2
      best=failed
      break
    fi
    read -r seconds kb < <(tail -n 1 "$tmp/time")
    rss=$((kb / 1024))
    if [ -z "$best" ] || awk -v a="$seconds" -v b="$best" 'BEGIN { exit !(a < b) }'; then best=$seconds; fi
  done
  printf -v "$var" '%s' "$best"
}
# ratio A B: A / B, ">x" when A was cut, "-" when either has no figure.
ratio() {
  awk -v a="$1" -v b="$2" 'BEGIN {
    if (b !~ /^[0-9.]+$/ || a == "failed" || a == "-") printf "-"
    else if (a ~ /^>/) printf ">%.1f", substr(a, 2) / b
    else printf "%.2f", a / b }'
}

printf '%-20s %4s %9s %-20s %6s %6s %8s %6s %6s %7s %10s %7s %7s %6s %8s %7s\n' \
  mesh res triangles sign load tree distance sign save "total s" "voxels/s" "RSS MB" before ratio openvdb ratio
for mesh in "${meshes[@]}"; do
  for res in $resolutions; do
    [ "$(basename "$mesh")" = tetra-copies.obj ] && [ "$res" != "${resolutions%% *}" ] && continue
    if ! timeout "$limit" "$sdfgen" bench "$mesh" --res "$res" --repeat "$repeat" >"$tmp/bench" 2>&1; then
      echo "speed.sh: sdfgen bench failed or ran past ${limit}s on $mesh at res $res" >&2
      tail -n 3 "$tmp/bench" >&2
      continue
    fi
    # bench's columns: mesh triangles dims sign load tree distance sign save total voxels/s ...
    row=$(awk 'f { print; exit } /^mesh/ { f = 1 }' "$tmp/bench")
    timed total "$sdfgen" bake "$mesh" --res "$res" -o "$tmp/sdfgen.npy"
    sdfgen_rss=$rss
    samples=$(awk '{ split($3, d, "x"); print d[1] * d[2] * d[3] }' <<<"$row")
    old=- vdb=-
    [ -z "$before" ] || timed old "$before" bake "$mesh" --res "$res" -o "$tmp/before.npy"
    [ ! -x "$openvdb" ] || timed vdb "$openvdb" "$mesh" --res "$res" -o "$tmp/openvdb.npy"
    awk -v res="$res" -v total="$total" -v samples="$samples" -v rss="$sdfgen_rss" -v old="$old" -v oldRatio="$(ratio "$old" "$total")" \
      -v vdb="$vdb" -v vdbRatio="$(ratio "$vdb" "$total")" \
      '{ rate = total ~ /^[0-9.]+$/ ? sprintf("%.0f", samples / total) : "-"
         printf "%-20s %4s %9s %-20s %6s %6s %8s %6s %6s %7s %10s %7s %7s %6s %8s %7s\n", $1, res, $2, $4, $5, $6, $7, $8, $9, total, rate, rss, old, oldRatio, vdb, vdbRatio }' <<<"$row"
  done
done
echo "(phases: seconds from sdfgen bench, tree includes the closest-point tree and topology, sign the mesh check when auto needs it; total: wall"
echo " seconds of the whole 'sdfgen bake -o .npy' process, voxels/s over it; RSS: its peak resident memory;"
echo " before, openvdb: wall seconds of the other binary's whole process on the same grid, each ratio = its"
echo " seconds / sdfgen's; $(nproc) cores, best of $repeat)"
