#!/usr/bin/env bash
# Configures and builds the sanitizer build, build-sanitize/: clang, AddressSanitizer +
# UndefinedBehaviorSanitizer, libFuzzer instrumentation, no viewer. test.sh's unit tests and
# tests/fuzz/run.sh's harnesses both use it. Usage: scripts/build-sanitize.sh [-- TARGETS...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
[ "${1:-}" = -- ] && shift
exec "$root/scripts/build.sh" "$root/build-sanitize" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDFGEN_FUZZ=ON -DSDFGEN_VIEWER=OFF \
  -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -- "$@"
