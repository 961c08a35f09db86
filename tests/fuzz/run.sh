#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan) in build-sanitize/ (scripts/build-sanitize.sh) and
# runs each for a while.
# Usage: tests/fuzz/run.sh [--parallel] [DURATION [HARNESS...]]
#        tests/fuzz/run.sh --count   (prints how many harnesses a plain run runs)
#   --parallel: run the harnesses at the same time (one core each) instead of one after another.
#   DURATION per harness: seconds, or with a suffix: 20s, 30m, 2h (default 20s).
#   HARNESS: obj, ply, mesh (OFF, STL, glTF, GLB), bake, and the field readers field (.sdf), npy, npz, nrrd, vdb (default: all).
# Each starts from its seed corpus (tests/fuzz/corpus/HARNESS) plus what earlier runs found
# (build-sanitize/corpus/HARNESS); crashes are written to build-sanitize/crashes/HARNESS/ and stop the run
# with a non-zero exit. Long runs: `nice tests/fuzz/run.sh 2h` (two hours each, one after another).
# FUZZ_TIMEOUT=SECONDS (default 10) is libFuzzer's per-input wall-clock limit: raise it for runs at a
# low priority on a busy machine, where an input can wait longer than that for a core.
# FUZZ_SEED=N fixes libFuzzer's random seed, so that a short run tries the same inputs each time
# (test.sh's smoke runs: a finding is then one to reproduce, not a roll of the dice); long runs
# leave it unset and explore afresh.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
all_harnesses=(obj ply mesh field npy npz nrrd vdb bake)
[ "${1:-}" = --count ] && echo ${#all_harnesses[@]} && exit 0
parallel=0
[ "${1:-}" = --parallel ] && parallel=1 && shift
duration=${1:-20s}
shift || true
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=("${all_harnesses[@]}")
case $duration in
  *h) seconds=$(( ${duration%h} * 3600 )) ;;
  *m) seconds=$(( ${duration%m} * 60 )) ;;
  *s) seconds=${duration%s} ;;
  *) seconds=$duration ;;
esac

build=$root/build-sanitize
targets=()
for h in "${harnesses[@]}"; do targets+=("fuzz_$h"); done
"$root/scripts/build-sanitize.sh" -- "${targets[@]}"

# The harnesses write each input to a file (the loaders read paths); in memory, that costs little.
[ -d /dev/shm ] && [ -w /dev/shm ] && export TMPDIR=${TMPDIR:-/dev/shm}
fuzz() {
  local h=$1 corpus=$build/corpus/$1 crashes=$build/crashes/$1 dict=$root/tests/fuzz/$1.dict max_len=4096
  local log=$build/fuzz_$1.$$.log # one per run: two runs at once must not share a log
  mkdir -p "$corpus" "$crashes"
  case $h in
    bake) dict=$root/tests/fuzz/obj.dict ;;
    npz) dict=$root/tests/fuzz/npy.dict; max_len=8192 ;; # a band field's smallest stored archive is 4.3 KB (one brick)
    vdb) max_len=16384 ;; # a dense grid's smallest file is 10 KB (one leaf and its parents' masks)
  esac
  echo "fuzz_$h: ${seconds} s"
  # -rss_limit_mb and -malloc_limit_mb catch memory blow-ups (the loaders must refuse, not
  # allocate, what they cannot hold).
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 LSAN_OPTIONS="suppressions=$root/tests/lsan.supp" \
    "$build/tests/fuzz/fuzz_$h" "$corpus" "$root/tests/fuzz/corpus/$h" -max_total_time="$seconds" -dict="$dict" \
    -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout="${FUZZ_TIMEOUT:-10}" ${FUZZ_SEED:+-seed="$FUZZ_SEED"} -max_len=$max_len -artifact_prefix="$crashes/" -print_final_stats=1 \
    >"$log" 2>&1 || { tail -n 60 "$log"; echo "fuzz_$h found a problem: see $crashes"; return 1; }
  grep -aE '^(Done|stat::(number_of_executed_units|new_units_added|peak_rss_mb))' "$log" | sed "s/^/fuzz_$h: /"
}

status=0
if [ $parallel = 1 ]; then
  pids=()
  for h in "${harnesses[@]}"; do fuzz "$h" & pids+=($!); done
  for pid in "${pids[@]}"; do wait "$pid" || status=1; done
else
  for h in "${harnesses[@]}"; do fuzz "$h" || status=1; done
fi
exit $status
