#!/bin/sh
# Save/load benchmark of every field format: bakes MESH (default: the Stanford bunny in
# ../shared/meshes, else the bundled bunny) once at --res (default 256) into a temporary .npy,
# then times saving and loading it in each format with bench_formats.
#   bench/formats.sh [MESH] [RES]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
mesh=${1:-$root/../shared/meshes/stanford-bunny.obj}
[ -f "$mesh" ] || mesh=$root/assets/bunny.obj
res=${2:-256}
cmake --build "$root/build" --target sdfgen bench_formats > /dev/null
field=$(mktemp --suffix=.npz)
trap 'rm -f "$field"' EXIT
"$root/build/sdfgen" bake "$mesh" --res "$res" -o "$field"
"$root/build/bench/bench_formats" "$field"
