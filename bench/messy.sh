#!/usr/bin/env bash
# Usage: bench/messy.sh [--triangles "5000 50000"] [--res 256] [--band-res 1024] [--threads N] [--timeout S]
#
# The exact winding sign's cost against the distance's on messy meshes, one failure class of real
# assets at a time (bench/messy_meshes.py: open parts, inside-out and nested parts, duplicates,
# thin double-sided panels, interpenetrating parts), at each --triangles size, plus the real and
# generated meshes beside the repository when there (../shared/meshes: the Stanford bunny, spot,
# suzanne, the teapot; bench/hard_meshes.py: the bunny with 1.4k holes and an open terrain sheet).
#
# Dense: `sdfgen bench MESH --res R --sign winding`, its distance and sign phases and their ratio.
# Band: the whole process of `sdfgen bake MESH --res B --band 3` to .npz, and its ratio to the
# Stanford bunny's (or the bundled bunny's) in the same run.
# With BASE=path/to/an/older/sdfgen (or a script that runs one), the same runs of that build are shown beside (before/after)
# and its band files are compared with this build's array for array (same: identical fields).
# --timeout S stops any run after S seconds (an old build's sign can take minutes): its figure
# reads ">S" and its ratios and comparison "-".
# Builds sdfgen in build/ (Release; BUILD=DIR for another folder); meshes and outputs go to
# BUILD/messy/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$root/build}
triangles="5000 50000"
res=256
band_res=1024
threads=0
timeout=0
while [ $# -gt 0 ]; do
  case $1 in
    --triangles) triangles=$2; shift 2 ;;
    --res) res=$2; shift 2 ;;
    --band-res) band_res=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --timeout) timeout=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "messy.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
command -v /usr/bin/time >/dev/null || { echo "messy.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
"$root/scripts/build.sh" "$build" -DCMAKE_BUILD_TYPE=Release -- sdfgen >/dev/null
sdfgen=$build/sdfgen
work=$build/messy
mkdir -p "$work"

meshes=()
shared=$root/../shared/meshes
if [ -f "$shared/stanford-bunny.obj" ]; then
  reference=$(cd "$shared" && pwd)/stanford-bunny.obj
  [ -f "$work/hard/bunny-holes.obj" ] || /usr/bin/python3 "$root/bench/hard_meshes.py" "$reference" "$work/hard" >/dev/null
  meshes+=("$reference" "$work/hard/bunny-holes.obj")
  for name in spot suzanne teapot; do
    if [ -f "$shared/$name.obj" ]; then meshes+=("$(cd "$shared" && pwd)/$name.obj"); fi
  done
  meshes+=("$work/hard/terrain.obj")
else
  reference=$root/assets/bunny.obj
  meshes+=("$reference")
fi
for n in $triangles; do
  [ -f "$work/$n/open-parts.obj" ] || /usr/bin/python3 "$root/bench/messy_meshes.py" "$work/$n" --triangles "$n" >/dev/null
  for f in "$work/$n"/*.obj; do meshes+=("$f"); done
done

limited() { if [ "$timeout" != 0 ]; then timeout "$timeout" "$@"; else "$@"; fi; }
# phases BIN MESH: prints the distance and sign seconds of `bench` (best of 2), or "- >S" past the
# timeout ("- failed" for another failure).
phases() {
  local out status=0
  out=$(limited "$1" bench "$2" --res "$res" --sign winding --threads "$threads" --repeat 2 2>/dev/null |
    awk -v name="$(basename "$2")" '$1 == name { print $(NF-6), $(NF-5) }') || status=$?
  if [ -n "$out" ]; then echo "$out"; elif [ "$status" = 124 ]; then echo "- >$timeout"; else echo "- failed"; fi
}
# band BIN MESH OUT: prints the wall seconds of the band bake to OUT, ">S" past the timeout, or
# "failed".
band() {
  rm -f "$3"
  local status=0
  limited /usr/bin/time -f '%e' -o "$3.time" "$1" bake "$2" --res "$band_res" --band 3 --threads "$threads" -o "$3" >/dev/null 2>&1 ||
    status=$?
  case $status in
    0) cat "$3.time" ;;
    124) echo ">$timeout" ;;
    *) echo failed ;;
  esac
}
# ratio A B: A / B with two decimals, or "-" where either is not a number.
ratio() { case "$1$2" in *[!0-9.]*) echo - ;; *) printf "%.2f" "$(echo "$1 / $2" | bc -l)" ;; esac; }

label() { case $1 in "$work"/*/*) echo "$(basename "$(dirname "$1")")/$(basename "$1" .obj)" ;; *) basename "$1" .obj ;; esac; }
bunny_band=$(band "$sdfgen" "$reference" "$work/reference.npz")
echo "sdfgen messy-mesh benchmark: dense res $res (sign winding), band res $band_res band 3, threads $threads (0: all); reference band: $(label "$reference") $bunny_band s"
if [ -n "${BASE:-}" ]; then
  printf "%-28s %9s %9s %7s | %9s %6s | %8s %6s | %9s %6s %s\n" mesh distance sign ratio "base sign" faster band "/bunny" "base band" faster same
else
  printf "%-28s %9s %9s %7s | %8s %6s\n" mesh distance sign ratio band "/bunny"
fi
for mesh in "${meshes[@]}"; do
  read -r distance sign < <(phases "$sdfgen" "$mesh")
  seconds=$(band "$sdfgen" "$mesh" "$work/new.npz")
  line=$(printf "%-28s %9s %9s %7s | %8s %6s" "$(label "$mesh")" "$distance" "$sign" "$(ratio "$sign" "$distance")" \
    "$seconds" "$(ratio "$seconds" "$bunny_band")")
  if [ -n "${BASE:-}" ]; then
    read -r _ base_sign < <(phases "$BASE" "$mesh")
    base_seconds=$(band "$BASE" "$mesh" "$work/base.npz")
    same=-
    [ -f "$work/new.npz" ] && [ -f "$work/base.npz" ] &&
      same=$(/usr/bin/python3 -c "import numpy as np, sys; a, b = np.load(sys.argv[1]), np.load(sys.argv[2]); print('yes' if a.files == b.files and all(np.array_equal(a[k], b[k]) for k in a.files) else 'NO')" "$work/new.npz" "$work/base.npz")
    line=$(printf "%s | %9s %6s | %9s %6s %s" "$line" "$base_sign" "$(ratio "$base_sign" "$sign")" "$base_seconds" \
      "$(ratio "$base_seconds" "$seconds")" "$same")
    # the columns in the header's order
    line=$(echo "$line" | awk -F'|' '{ printf "%s|%s|%s|%s\n", $1, $3, $2, $4 }')
  fi
  echo "$line"
done
rm -f "$work"/*.npz "$work"/*.time
