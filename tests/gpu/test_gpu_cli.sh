#!/usr/bin/env bash
# The command line's GPU device end to end (ctest gpu-cli, release build only): usage:
# test_gpu_cli.sh SDFGEN_BINARY REPO_ROOT. Runs under whatever OpenGL 4.5 driver there is (llvmpipe in CI).
set -u
sdfgen=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/../support/check.sh"

bunny=$root/assets/bunny.obj
expect 0 '^GPU device: GL vendor .*, renderer .*, version 4\.[5-9]' -- "$sdfgen" info
expect 0 '^--device auto: (cpu|gpu): ' -- "$sdfgen" info
expect 0 'device: gpu: GL vendor' -- "$sdfgen" bake "$bunny" -o "$work/gpu.sdf" --res 20 --device gpu --sign winding
expect 0 'device: cpu' -- "$sdfgen" bake "$bunny" -o "$work/cpu.sdf" --res 20 --device cpu --sign winding
expect 0 'signs differ: 0 samples' -- "$sdfgen" compare "$work/gpu.sdf" "$work/cpu.sdf"
expect 0 'max [0-9.e-]+ \(([0-9.]+e-0[5-9]|0) voxels\)' -- "$sdfgen" compare "$work/gpu.sdf" "$work/cpu.sdf"
expect 1 '^sdfgen: --device: device gpu computes exact distances; method rays runs on the CPU$' -- \
  "$sdfgen" bake "$bunny" -o "$work/x.sdf" --res 8 --method rays --device gpu
expect fail 'device' -- "$sdfgen" bake "$bunny" -o "$work/x.sdf" --device tpu
# Batch status lines name the device and its renderer.
mkdir -p "$work/meshes" && cp "$bunny" "$work/meshes/"
expect 0 '^\[1/1\] done .*bunny\.sdf \([0-9.]+ s, gpu [^)]+\)' -- \
  "$sdfgen" batch "$work/meshes" --out "$work/batch" --format sdf --res 12 --device gpu --status "$work/status.jsonl"
expect 0 '"device":"gpu ' -- cat "$work/status.jsonl"
# The renderer's implicit bake on the GPU, drawn through EGL.
expect 0 '' -- "$sdfgen" render "$bunny" -o "$work/slice.png" --view slice --res 16 --device gpu --size 64x48
expect 0 'P +N +G' -- od -An -c -N4 "$work/slice.png"
# No OpenGL 4.5: a clear one-line error for gpu, the CPU for auto, nothing written on failure.
expect 1 '^sdfgen: device gpu: EGL: no OpenGL 4\.5 core context .*OSMesa: could not create an OpenGL 4\.5 core context' -- \
  env MESA_GL_VERSION_OVERRIDE=3.3 "$sdfgen" bake "$bunny" -o "$work/none.sdf" --res 8 --device gpu
expect fail '' -- test -e "$work/none.sdf"
expect 0 'device: cpu' -- env MESA_GL_VERSION_OVERRIDE=3.3 "$sdfgen" bake "$bunny" -o "$work/auto.sdf" --res 8 --device auto
expect 0 '^GPU device: none \(.*4\.5' -- env MESA_GL_VERSION_OVERRIDE=3.3 "$sdfgen" info

# The context can be forced; a wrong name is named.
expect 0 'through OSMesa' -- env SDFGEN_HEADLESS=osmesa "$sdfgen" info
expect 0 "^GPU device: none \(device gpu: SDFGEN_HEADLESS is 'vulkan'; expected egl or osmesa" -- env SDFGEN_HEADLESS=vulkan "$sdfgen" info

echo "gpu-cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
