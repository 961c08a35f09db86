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
scripts/build-sanitize.sh -- sdfgen sdfgen_tests fuzz_obj fuzz_field fuzz_npy fuzz_npz fuzz_nrrd fuzz_vdb fuzz_bake fuzz_ply fuzz_mesh
LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp" ctest --test-dir build-sanitize --output-on-failure -j "$jobs" -LE "render|gui|gpu|install"
# libFuzzer harnesses (each mesh and field reader, load -> tree -> bake), about 15 s of CPU each,
# from the seed corpus in tests/fuzz/corpus, side by side on every core. tests/fuzz/run.sh 2h runs
# them for hours. A fixed seed: the same inputs on every run.
fuzz_count=$(tests/fuzz/run.sh --count)
FUZZ_SEED=1 tests/fuzz/run.sh --parallel "$(( (15 * fuzz_count + jobs - 1) / jobs ))s"
