#!/usr/bin/env bash
# GPU figures in one go, for a machine with a GPU (minutes of it): builds the release tree (plain
# cmake: no package installs, the machine may be offline), prints the OpenGL driver, checks GPU ==
# CPU (the gpu-labelled tests on small grids, then every sample of the mesh's field at the
# resolutions up to 256 with `sdfgen compare`: "max 0" means bit-identical), and times the mesh on
# the GPU (best of 3, with the device's own phase times from SDFGEN_GPU_TIMES) and on the CPU.
#
# Usage: bench/gpu.sh [MESH] [RES ...]
#   default mesh: ../shared/meshes/stanford-bunny.obj when present (69,451 triangles, holes: sign
#   auto picks winding), else the bundled bunny; default resolutions: 128 256 512.
#   SDFGEN_BUILD picks the build folder (default build-gpu).
#   SDFGEN_BIN=DIR runs prebuilt binaries instead (a folder made by bench/gpu-bundle.sh on a machine
#   with the Debian packages, for a GPU machine without them): no build, no ctest.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SDFGEN_BUILD:-$root/build-gpu}
mesh=${1:-$root/../shared/meshes/stanford-bunny.obj}
[ -f "$mesh" ] || mesh=$root/assets/bunny.obj
shift || true
resolutions=("$@")
[ ${#resolutions[@]} -gt 0 ] || resolutions=(128 256 512)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ -n "${SDFGEN_BIN:-}" ]; then
  sdfgen=$SDFGEN_BIN/sdfgen
else
  [ -f "$build/build.ninja" ] || cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSDFGEN_PYTHON=OFF >/dev/null
  cmake --build "$build" --target sdfgen sdfgen_gpu_tests
  sdfgen=$build/sdfgen
fi
echo "== machine: $(nproc) cores; $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi')"
"$sdfgen" info

echo "== GPU == CPU on small grids (ctest -L gpu)"
if [ -n "${SDFGEN_BIN:-}" ]; then
  "$SDFGEN_BIN/sdfgen_gpu_tests" --gtest_filter=-GpuBadContext.*
else
  ctest --test-dir "$build" -L gpu --output-on-failure
fi

echo "== $mesh"
for res in "${resolutions[@]}"; do
  if [ "$res" -le 256 ]; then
    "$sdfgen" bake "$mesh" -o "$work/gpu.sdf" --res "$res" --device gpu
    "$sdfgen" bake "$mesh" -o "$work/cpu.sdf" --res "$res" --device cpu
    echo "-- res $res, GPU vs CPU, every sample:"
    "$sdfgen" compare "$work/gpu.sdf" "$work/cpu.sdf"
    rm -f "$work/gpu.sdf" "$work/cpu.sdf"
  fi
  echo "-- res $res, GPU (best of 3; the first run opens the device and compiles the shaders):"
  SDFGEN_GPU_TIMES=1 "$sdfgen" bench "$mesh" --res "$res" --device gpu --repeat 3
  echo "-- res $res, CPU ($(nproc) threads):"
  "$sdfgen" bench "$mesh" --res "$res" --device cpu
done
