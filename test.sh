#!/usr/bin/env bash
# Builds sdfgen and runs every test: the release build, then again under AddressSanitizer and
# UndefinedBehaviorSanitizer in its own build folder (render and GUI tests excluded there).
set -euo pipefail
cd "$(dirname "$0")"
jobs=$(nproc)
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release
ctest --test-dir build --output-on-failure -j "$jobs"
scripts/build.sh build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDFGEN_SANITIZE=ON -- sdfgen sdfgen_tests
# The render and GUI tests (labels render, gui) run in the release build only: Mesa's llvmpipe is not built with
# the sanitizers.
ctest --test-dir build-sanitize --output-on-failure -j "$jobs" -LE "render|gui|gpu"
