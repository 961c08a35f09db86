#!/usr/bin/env bash
# Builds sdfgen (installing missing Debian packages first) and bakes the bundled bunny.
# Extra arguments go to `sdfgen bake`, e.g. ./run.sh --res 128 --rays 64
set -euo pipefail
cd "$(dirname "$0")"
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -- sdfgen
mkdir -p out
./build/sdfgen bake assets/bunny.obj -o out/bunny.sdf "$@"
