#!/usr/bin/env bash
# Packs the release build's `sdfgen` and `sdfgen_gpu_tests` with the shared libraries they load
# (all but the C and C++ runtimes and the OpenGL/EGL loaders, which must be the GPU machine's own:
# its driver may need newer ones) and the shaders into one folder, for a GPU machine that lacks the Debian packages. There:
#   LD_LIBRARY_PATH=DIR/lib SDFGEN_BIN=DIR bench/gpu.sh [MESH] [RES ...]
#
# Usage: bench/gpu-bundle.sh OUTDIR   (BUILD picks the build folder, default build)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$root/build}
out=${1:?usage: bench/gpu-bundle.sh OUTDIR}
cmake --build "$build" --target sdfgen sdfgen_gpu_tests
mkdir -p "$out/lib"
cp "$build/sdfgen" "$build/tests/sdfgen_gpu_tests" "$out/"
cp -r "$root/shaders" "$out/"
keep_out='^(linux-vdso|ld-linux|libc\.|libm\.|libdl\.|libpthread\.|librt\.|libstdc\+\+|libgcc_s|libGL|libEGL|libOpenGL|libGLX|libGLdispatch)'
for binary in "$out/sdfgen" "$out/sdfgen_gpu_tests"; do
  ldd "$binary" | awk '$3 ~ /^\// {print $1, $3}' | while read -r name path; do
    [[ $name =~ $keep_out ]] || cp -L "$path" "$out/lib/$name"
  done
done
du -sh "$out"
