#!/usr/bin/env bash
# Usage: bench/band.sh [MESH.obj ...] [--res "256 512 1024 2048 4096"] [--band 3]
#
# The narrow-band bake against OpenVDB's narrow-band path, the whole process to a .vdb level set,
# one mesh and resolution at a time: `sdfgen bake MESH --res N --band V -o F.vdb` and
# `peer_openvdb MESH --res N --band V -o F.vdb` (tools::meshToLevelSet on the same grid). Prints,
# per resolution, each tool's wall-clock seconds and peak resident memory (GNU time), their
# ratios, and sdfgen's growth per doubling of the resolution. At resolutions whose dense field
# fits (up to 512), it also bakes the dense field and counts the samples whose side differs from
# it: sdfgen's band field (by `sdfgen compare`) and OpenVDB's level set (peer_openvdb --signs-against).
#
# Default mesh: ../shared/meshes/stanford-bunny.obj beside the repository if there, else
# assets/bunny.obj. Builds sdfgen and peer_openvdb in build-peers/ (Release; BUILD=DIR for another
# folder); the files go to BUILD/band-out/ and are deleted after each resolution.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$root/build-peers}
out=$build/band-out
resolutions="256 512 1024 2048 4096"
band=3
meshes=()
while [ $# -gt 0 ]; do
  case $1 in
    --res) resolutions=$2; shift 2 ;;
    --band) band=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "band.sh: unknown option $1" >&2; exit 2 ;;
    *) meshes+=("$1"); shift ;;
  esac
done
if [ ${#meshes[@]} -eq 0 ]; then
  if [ -f "$root/../shared/meshes/stanford-bunny.obj" ]; then
    meshes=("$(cd "$root/../shared/meshes" && pwd)/stanford-bunny.obj")
  else
    meshes=("$root/assets/bunny.obj")
  fi
fi
command -v /usr/bin/time >/dev/null || { echo "band.sh: needs GNU time (apt-get install time)" >&2; exit 1; }

generator=()
[ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null && generator=(-G Ninja)
mkdir -p "$build" "$out"
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >"$build/band-configure.log" 2>&1 ||
  { cat "$build/band-configure.log" >&2; exit 1; }
cmake --build "$build" --target sdfgen peer_openvdb >"$build/band-build.log" 2>&1 ||
  { tail -n 40 "$build/band-build.log" >&2; echo "band.sh: build failed" >&2; exit 1; }
sdfgen=$build/sdfgen
peer=$build/bench/peer_openvdb

# measure LOG COMMAND...: sets $seconds and $megabytes (peak resident set) of the whole process.
measure() {
  local log=$1
  shift
  /usr/bin/time -f '%e %M' -o "$log.time" "$@" >"$log" 2>&1 || { tail -n 3 "$log" >&2; return 1; }
  read -r seconds kilobytes <"$log.time"
  megabytes=$((kilobytes / 1024))
}

for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .obj)
  echo "== $mesh, band $band voxels each side, $(nproc) cores"
  printf '%6s | %9s %8s | %9s %8s | %7s %7s | %7s | %s\n' res "sdfgen s" "MB" "openvdb s" "MB" "speed" "memory" growth "wrong signs (sdfgen / openvdb)"
  last=
  for res in $resolutions; do
    measure "$out/sdfgen.log" "$sdfgen" bake "$mesh" --res "$res" --band "$band" -o "$out/$name-sdfgen.vdb"
    s_seconds=$seconds s_mb=$megabytes
    signs=-
    if [ "$res" -le 512 ]; then
      "$sdfgen" bake "$mesh" --res "$res" -o "$out/$name-dense.npz" >/dev/null
      measure "$out/openvdb.log" "$peer" "$mesh" --res "$res" --band "$band" -o "$out/$name-openvdb.vdb" --signs-against "$out/$name-dense.npz"
      ours=$("$sdfgen" compare "$out/$name-sdfgen.vdb" "$out/$name-dense.npz" | grep -o 'signs differ: .*' | sed 's/signs differ: //' || true)
      theirs=$(grep -o 'wrong signs: .*' "$out/openvdb.log" | sed 's/wrong signs: //')
      signs="$ours / $theirs"
    else
      measure "$out/openvdb.log" "$peer" "$mesh" --res "$res" --band "$band" -o "$out/$name-openvdb.vdb"
    fi
    o_seconds=$seconds o_mb=$megabytes
    growth=-
    [ -n "$last" ] && growth=$(awk -v a="$s_seconds" -v b="$last" 'BEGIN { printf "%.1fx", a / b }')
    last=$s_seconds
    printf '%6s | %9s %8s | %9s %8s | %6sx %6sx | %7s | %s\n' "$res" "$s_seconds" "$s_mb" "$o_seconds" "$o_mb" \
      "$(awk -v a="$o_seconds" -v b="$s_seconds" 'BEGIN { printf "%.2f", a / b }')" \
      "$(awk -v a="$o_mb" -v b="$s_mb" 'BEGIN { printf "%.2f", a / b }')" "$growth" "$signs"
    rm -f "$out/$name-"*.vdb "$out/$name-dense.npz"
  done
done
