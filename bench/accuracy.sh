#!/usr/bin/env bash
# Accuracy table: each method and sign against the brute-force reference (every triangle for every
# sample in double, exact winding number), on the same grid.
# Usage: bench/accuracy.sh [--res N] [MESH ...]   (default: the bundled bunny and ../shared/meshes/*.obj)
#        bench/accuracy.sh --rays-table [bench_ray_error options]
# --rays-table prints instead the ray method's error against a sphere's analytic distance for
# 16 to 1024 rays (bench/ray_error.cpp; the table in docs/how-it-works.md, "Distances").
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
res=48
meshes=()
if [ "${1:-}" = --rays-table ]; then
  shift
  "$root/scripts/build.sh" "$root/build" -DCMAKE_BUILD_TYPE=Release -- bench_ray_error >/dev/null
  exec "$root/build/bench/bench_ray_error" "$@"
fi
while [ $# -gt 0 ]; do
  case $1 in
    --res) res=$2; shift 2 ;;
    *) meshes+=("$1"); shift ;;
  esac
done
if [ ${#meshes[@]} -eq 0 ]; then
  meshes=("$root/assets/bunny.obj")
  for m in "$root"/../shared/meshes/*.obj; do [ -f "$m" ] && meshes+=("$m"); done
fi
"$root/scripts/build.sh" "$root/build" -DCMAKE_BUILD_TYPE=Release -- sdfgen >/dev/null
sdfgen=$root/build/sdfgen
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# field NAME ARGS...: bake into $work/NAME.sdf
field() { local name=$1; shift; "$sdfgen" bake "$mesh" -o "$work/$name.sdf" --res "$res" "$@" >"$work/$name.log"; }
# metric A B BAND FIELD: FIELD = max|mean|signs from `sdfgen compare`, distances in voxels, signs in %
metric() {
  "$sdfgen" compare "$work/$1.sdf" "$work/$2.sdf" --band "$3" | awk -v f="$4" '
    /abs difference/ { gsub(/[(),]/, ""); max = $5; mean = $9 }
    /signs differ/ { gsub(/[(%)]/, ""); signs = $5 }
    END { if (f == "max") printf "%.3g", max; else if (f == "mean") printf "%.3g", mean; else printf "%.3g%%", signs }'
}

echo "res $res; distances in voxels; wrong signs: fraction of samples farther than one voxel from the surface"
echo
echo "| mesh | triangles | auto picks | exact max err | rays-64 max err | rays-64 mean err | wrong signs: rays | pseudonormal | winding | auto |"
echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|"
for mesh in "${meshes[@]}"; do
  field brute --method brute
  field exact --method exact --sign auto
  field exact_winding --method exact --sign winding
  field exact_pseudo --method exact --sign pseudonormal
  field exact_rays --method exact --sign rays --rays 64
  field rays_winding --method rays --sign winding --rays 64
  triangles=$(grep -o '[0-9]* triangles' "$work/exact.log" | cut -d' ' -f1)
  picks=$(grep -o 'sign auto/[a-z]*' "$work/exact.log" | cut -d/ -f2)
  printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$(basename "$mesh" .obj)" "$triangles" "$picks" \
    "$(metric brute exact 0 max)" "$(metric exact_winding rays_winding 0 max)" "$(metric exact_winding rays_winding 0 mean)" \
    "$(metric brute exact_rays 1 signs)" "$(metric brute exact_pseudo 1 signs)" "$(metric brute exact_winding 1 signs)" \
    "$(metric brute exact 1 signs)"
done
