#!/usr/bin/env bash
# Usage: scripts/build.sh BUILD_DIR [CMAKE_OPTIONS...] [-- TARGETS...]
# Installs missing Debian packages, configures BUILD_DIR once (again when options change), builds.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=$1
shift
options=()
targets=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do options+=("$1"); shift; done
[ $# -gt 0 ] && shift && targets=("$@")

"$root/scripts/setup.sh"
stamp="$dir/.sdfgen-options"
if [ ! -f "$dir/build.ninja" ] || [ "$(cat "$stamp" 2>/dev/null)" != "${options[*]-}" ]; then
  cmake -S "$root" -B "$dir" -G Ninja "${options[@]}" >/dev/null
  echo "${options[*]-}" >"$stamp"
fi
if [ ${#targets[@]} -gt 0 ]; then
  cmake --build "$dir" --target "${targets[@]}"
else
  cmake --build "$dir"
fi
