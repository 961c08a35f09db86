#!/usr/bin/env bash
# Builds sdfgen and runs every test: the release build, then again under AddressSanitizer and
# UndefinedBehaviorSanitizer in its own build folder (clang, without the viewer), then the fuzzers.
set -euo pipefail
cd "$(dirname "$0")"
jobs=$(nproc)
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release
ctest --test-dir build --output-on-failure -j "$jobs"
# The sanitizer build is also the core-only build (-DSDFGEN_VIEWER=OFF): it proves the library and CLI
# configure and build without OpenGL, GLFW, ImGui, OSMesa, EGL or glad. The render, GUI and GPU tests need the
# viewer, and Mesa's llvmpipe is not built with the sanitizers anyway; the install test links a
# consumer without them. It is clang's, with the libFuzzer harnesses (-DSDFGEN_FUZZ=ON), so that
# the unit tests and the fuzzers share one instrumented build of the core.
scripts/build-sanitize.sh -- sdfgen sdfgen_tests fuzz_obj fuzz_field fuzz_bake fuzz_ply fuzz_mesh
LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp" ctest --test-dir build-sanitize --output-on-failure -j "$jobs" -LE "render|gui|gpu|install"
# libFuzzer harnesses (OBJ loader, field reader, load -> tree -> bake, PLY reader, OFF/STL/glTF/GLB
# readers), about 15 s of CPU each, from the seed corpus in tests/fuzz/corpus: side by side on up to
# five cores, so each runs 75 s / cores (38 s on 2 cores rather than 15 s each one after another).
# tests/fuzz/run.sh 2h runs them for hours.
fuzz_cores=$(( jobs < 5 ? jobs : 5 ))
tests/fuzz/run.sh --parallel "$(( (75 + fuzz_cores - 1) / fuzz_cores ))s"
