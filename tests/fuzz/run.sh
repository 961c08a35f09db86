#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan) in build-fuzz/ and runs each for a while.
# Usage: tests/fuzz/run.sh [DURATION [HARNESS...]]
#   DURATION per harness: seconds, or with a suffix: 20s, 30m, 2h (default 20s).
#   HARNESS: obj, field, bake (default: all).
# Each starts from its seed corpus (tests/fuzz/corpus/HARNESS) plus what earlier runs found
# (build-fuzz/corpus/HARNESS); crashes are written to build-fuzz/crashes/HARNESS/ and stop the run
# with a non-zero exit. Long runs: `nice tests/fuzz/run.sh 2h` (about 6 hours for all three).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
duration=${1:-20s}
shift || true
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(obj field bake)
case $duration in
  *h) seconds=$(( ${duration%h} * 3600 )) ;;
  *m) seconds=$(( ${duration%m} * 60 )) ;;
  *s) seconds=${duration%s} ;;
  *) seconds=$duration ;;
esac

build=$root/build-fuzz
targets=()
for h in "${harnesses[@]}"; do targets+=("fuzz_$h"); done
"$root/scripts/build.sh" "$build" -DSDFGEN_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_COMPILER=clang -- "${targets[@]}"

# The harnesses write each input to a file (the loaders read paths); in memory, that costs little.
[ -d /dev/shm ] && [ -w /dev/shm ] && export TMPDIR=${TMPDIR:-/dev/shm}
for h in "${harnesses[@]}"; do
  corpus=$build/corpus/$h
  crashes=$build/crashes/$h
  mkdir -p "$corpus" "$crashes"
  dict=$root/tests/fuzz/$h.dict
  [ "$h" = bake ] && dict=$root/tests/fuzz/obj.dict
  echo "fuzz_$h: ${seconds} s"
  # One worker per harness keeps the machine usable; -rss_limit_mb catches memory blow-ups
  # (the loaders must refuse, not allocate, what they cannot hold).
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$build/tests/fuzz/fuzz_$h" "$corpus" "$root/tests/fuzz/corpus/$h" -max_total_time="$seconds" -dict="$dict" \
    -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 -max_len=4096 -artifact_prefix="$crashes/" -print_final_stats=1 \
    2>&1 | grep -vE '^#[0-9]+.*(NEW|REDUCE|pulse)' || { echo "fuzz_$h found a problem: see $crashes"; exit 1; }
done
