#!/usr/bin/env bash
# `sdfgen batch` end to end: outputs, status lines, skips and --force, a mesh that fails, a timeout
# that is honoured and one that is not (a phase that ignores the cancel flag), a memory budget,
# shards that cover the list exactly once, and resuming after the batch is killed mid-way.
# usage: test_batch.sh SDFGEN_BINARY REPO_ROOT
set -u
sdfgen=$1
root=$(realpath "$2")
python=/usr/bin/python3
work=$(mktemp -d)
trap 'kill -9 $pending 2>/dev/null; rm -rf "$work"' EXIT
pending=
. "$(dirname "$0")/../support/check.sh"

# A few small closed meshes, one open one and two broken ones.
mkdir -p "$work/meshes/sub"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/meshes/tet.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/meshes/sub/open.obj"
printf 'v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/meshes/sub/tet.obj"
printf 'v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\nf 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n' >"$work/meshes/octahedron.obj"
printf 'v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n' >"$work/meshes/broken.obj"
printf 'v 0 0 0\nv 1 0 0\nl 1 2\n' >"$work/meshes/lines.obj"

out=$work/out
"$sdfgen" batch "$work/meshes" --out "$out" --format sdf --res 12 --status "$work/status.jsonl" --jobs 2 >"$work/run1.txt" 2>&1
rc=$?
check "a batch with failures exits 1 (got $rc)" test $rc -eq 1
check "every good mesh has its output" test -s "$out/tet.sdf" -a -s "$out/sub/tet.sdf" -a -s "$out/sub/open.sdf" -a -s "$out/octahedron.sdf"
check "no output for the broken meshes" test ! -e "$out/broken.sdf" -a ! -e "$out/lines.sdf"
check "no partial files are left" test -z "$(find "$out" -name '.*partial*')"
check "the outputs equal sdfgen bake's" bash -c "'$sdfgen' bake '$work/meshes/sub/open.obj' -o '$work/open.sdf' --res 12 >/dev/null &&
  '$sdfgen' compare '$work/open.sdf' '$out/sub/open.sdf' | grep -q 'max 0 '"
check "one status line per mesh, with grid and sign" json_check "$work/status.jsonl" '
len(lines) == 6 and sorted(l["mesh"].split("/meshes/")[1] for l in lines) == ["broken.obj", "lines.obj", "octahedron.obj", "sub/open.obj", "sub/tet.obj", "tet.obj"]
and all(l["status"] == "done" and l["error"] is None and len(l["dims"]) == 3 and max(l["dims"]) == 12 and len(l["origin"]) == 3
        and l["voxel"] > 0 and l["sign"].startswith("auto/") and l["seconds"] >= 0 and l["shard"] == "0/1"
        for l in lines if "broken" not in l["mesh"] and "lines" not in l["mesh"])
and [l["sign"] for l in lines if l["mesh"].endswith("sub/open.obj")] == ["auto/winding"]
and all(l["device"] == "cpu" for l in lines if l["status"] == "done")
and all(l["status"] == "failed" and l["dims"] is None for l in lines if "broken" in l["mesh"] or "lines" in l["mesh"])
and "broken.obj:2: vertex coordinate" in [l for l in lines if "broken" in l["mesh"]][0]["error"]
and "lines.obj: no triangles" in [l for l in lines if "lines" in l["mesh"]][0]["error"]'
check "the summary counts and names the failures" bash -c "grep -qE '^  done +4$' '$work/run1.txt' && grep -qE '^  failed +2$' '$work/run1.txt' &&
  grep -q 'meshes per hour' '$work/run1.txt' && grep -qE '^\[[0-9]/6\] done .*tet.sdf \([0-9.]+ s, cpu\)$' '$work/run1.txt' && grep -q 'slowest' '$work/run1.txt' && grep -q 'failed   .*broken.obj: .*broken.obj:2' '$work/run1.txt'"

# A rerun skips the finished meshes (their files are untouched) and retries the failed ones.
stat -c '%n %i %Y.%y' "$out"/*.sdf "$out"/sub/*.sdf >"$work/before.txt"
"$sdfgen" batch "$work/meshes" --out "$out" --format sdf --res 12 --status "$work/status2.jsonl" >"$work/run2.txt" 2>&1
check "the rerun skips every finished mesh" json_check "$work/status2.jsonl" '
sorted(l["status"] for l in lines) == ["failed", "failed", "skipped", "skipped", "skipped", "skipped"]'
stat -c '%n %i %Y.%y' "$out"/*.sdf "$out"/sub/*.sdf >"$work/after.txt"
check "skipped outputs are untouched" cmp "$work/before.txt" "$work/after.txt"
"$sdfgen" batch "$work/meshes" --out "$out" --format sdf --res 12 --force --status "$work/status3.jsonl" >/dev/null 2>&1
check "--force bakes again" json_check "$work/status3.jsonl" 'sorted(l["status"] for l in lines) == ["done"] * 4 + ["failed"] * 2'

# Shards: every mesh in exactly one, from --shard and from a Kubernetes index.
for i in 0 1 2; do
  "$sdfgen" batch "$work/meshes" --out "$work/sharded" --format sdf --res 8 --shard $i/3 --status "$work/shards.jsonl" >/dev/null 2>&1
done
JOB_COMPLETION_INDEX=1 "$sdfgen" batch "$work/meshes" --out "$work/k8s" --format sdf --res 8 --shard-count 3 --status "$work/k8s.jsonl" >/dev/null 2>&1
check "three shards cover the list once" json_check "$work/shards.jsonl" '
len(lines) == 6 and len({l["mesh"] for l in lines}) == 6 and sorted(l["shard"] for l in lines) == ["0/3"] * 2 + ["1/3"] * 2 + ["2/3"] * 2'
check "JOB_COMPLETION_INDEX picks the same shard as --shard" bash -c "
  $python -c 'import json,sys; print(sorted(json.loads(l)[\"mesh\"] for l in open(sys.argv[1]) if json.loads(l)[\"shard\"] == \"1/3\"))' '$work/shards.jsonl' >'$work/a.txt' &&
  $python -c 'import json,sys; print(sorted(json.loads(l)[\"mesh\"] for l in open(sys.argv[1])))' '$work/k8s.jsonl' >'$work/b.txt' && cmp '$work/a.txt' '$work/b.txt'"
check "a bad shard is a one-line error" bash -c "'$sdfgen' batch '$work/meshes' --out '$work/x' --shard 3/3 2>&1 | grep -q 'index must be below the count'"

# Timeouts: the bundled bunny at res 160 takes seconds; cancelled after 0.3 s it stops at once. A FIFO
# as the mesh blocks in open(), which checks no cancel flag: the child is killed after the grace time.
bunny=$root/assets/bunny.obj
mkfifo "$work/stuck.obj"
printf '%s\tbunny.sdf\n%s\tstuck.sdf\n' "$bunny" "$work/stuck.obj" >"$work/slow.txt"
start=$(date +%s.%N)
"$sdfgen" batch "$work/slow.txt" --out "$work/slow" --format sdf --res 160 --timeout 0.3 --jobs 2 --status "$work/slow.jsonl" >"$work/slow-run.txt" 2>&1
elapsed=$($python -c "import sys; print(float(sys.argv[2]) - float(sys.argv[1]))" "$start" "$(date +%s.%N)")
check "timeouts are recorded: cancelled, and killed when cancelling does not work" json_check "$work/slow.jsonl" '
len(lines) == 2 and all(l["status"] == "failed" for l in lines)
and [l["error"] for l in lines if "bunny" in l["mesh"]] == ["timed out after 0.3 s"]
and "did not stop when cancelled: killed" in [l for l in lines if "stuck" in l["mesh"]][0]["error"]
and [l["seconds"] < 1.5 for l in lines if "bunny" in l["mesh"]] == [True]'
check "the timeouts took seconds, not the bake's time (took $elapsed s)" $python -c "import sys; sys.exit(not float(sys.argv[1]) < 8)" "$elapsed"

# A memory budget: res 400 needs 256 MiB for the values alone. The budget is an address-space
# limit, which AddressSanitizer's shadow memory cannot live under: not checked in that build.
printf '%s\n' "$bunny" >"$work/big.txt"
# GCC links AddressSanitizer as libasan.so, clang into the binary (which then exports __asan_init).
if ldd "$sdfgen" | grep -q libasan || nm -D "$sdfgen" 2>/dev/null | grep -q ' __asan_init$'; then
  echo "batch test: the memory budget check is skipped under AddressSanitizer"
else
  "$sdfgen" batch "$work/big.txt" --out "$work/big" --format sdf --res 500 --memory 200 --status "$work/big.jsonl" --timeout 20 >/dev/null 2>&1
  check "a mesh over the memory budget fails and says so" json_check "$work/big.jsonl" '
len(lines) == 1 and lines[0]["status"] == "failed" and "out of memory" in lines[0]["error"] and "200 MiB" in lines[0]["error"]'
fi

# Killed at any moment, a batch resumes: kill the whole batch (parent and child) while it bakes, rerun.
for n in 1 2 3 4 5 6; do printf '%s\tb%d.sdf\n' "$bunny" $n; done >"$work/resume.txt"
setsid "$sdfgen" batch "$work/resume.txt" --out "$work/resume" --format sdf --res 64 --status "$work/resume1.jsonl" >/dev/null 2>&1 &
pending=$!
for _ in $(seq 200); do
  [ -e "$work/resume/b2.sdf" ] && break
  sleep 0.05
done
kill -9 -- -$pending 2>/dev/null
wait $pending 2>/dev/null
pending=
finished=$(ls "$work/resume" | grep -c '^b.\.sdf$')
check "the killed batch had finished some but not all meshes ($finished)" test "$finished" -ge 2 -a "$finished" -lt 6
"$sdfgen" batch "$work/resume.txt" --out "$work/resume" --format sdf --res 64 --status "$work/resume2.jsonl" >/dev/null 2>&1
check "the rerun skips exactly the finished ones and bakes the rest" json_check "$work/resume2.jsonl" "
sum(l['status'] == 'skipped' for l in lines) == $finished and sum(l['status'] == 'done' for l in lines) == 6 - $finished and len(lines) == 6"
check "no partial file survives the rerun" test -z "$(find "$work/resume" -name '.*partial*')"
check "every resumed output is complete" bash -c "for f in '$work'/resume/b*.sdf; do '$sdfgen' compare \"\$f\" '$work/resume/b1.sdf' | grep -q 'max 0 ' || exit 1; done"

# `sdfgen sample` and `batch --format samples`: exactly n float32 points and distances, the same for a seed.
"$sdfgen" sample "$work/meshes/octahedron.obj" -n 1001 --seed 5 -o "$work/s1.npz" >"$work/sample.txt" 2>&1
"$sdfgen" sample "$work/meshes/octahedron.obj" -n 1001 --seed 5 --threads 1 -o "$work/s2.npz" >/dev/null 2>&1
check "sample writes points (n, 3) and sdf (n,) float32, the same for a seed" $python -c "
import numpy as np, sys
a, b = np.load(sys.argv[1]), np.load(sys.argv[2])
assert sorted(a.files) == ['points', 'sdf'] and a['points'].shape == (1001, 3) and a['sdf'].shape == (1001,)
assert a['points'].dtype == np.float32 and a['sdf'].dtype == np.float32
assert np.array_equal(a['points'], b['points']) and np.array_equal(a['sdf'], b['sdf'])
assert (a['sdf'] < 0).any() and (a['sdf'] > 0).any()" "$work/s1.npz" "$work/s2.npz"
check "sample prints its summary" grep -q '1001 samples (471 near, 470 far, 60 uniform), seed 5' "$work/sample.txt"
"$sdfgen" batch "$work/meshes" --out "$work/samples" --format samples --samples 300 --seed 1 >/dev/null 2>&1
check "batch --format samples writes one .npz of samples per mesh" $python -c "
import numpy as np, sys
assert np.load(sys.argv[1] + '/tet.npz')['points'].shape == (300, 3) and np.load(sys.argv[1] + '/sub/open.npz')['sdf'].shape == (300,)" "$work/samples"
check "sample without -n is an error" bash -c "! '$sdfgen' sample '$work/meshes/tet.obj' -o '$work/x.npz' 2>/dev/null"

check "bad arguments are one-line errors" bash -c "'$sdfgen' batch '$work/nothing' --out '$work/x' 2>&1 | grep -q 'nothing: no such file or folder'"

# Outputs named in a list stay inside --out: '..' and absolute paths are refused with the line.
printf '# two\nmeshes/tet.obj\t../x.npz\n' >"$work/up.txt"
printf 'meshes/tet.obj\t/abs/x.npz\n' >"$work/abs.txt"
check "a list output with '..' is refused with its line" bash -c "'$sdfgen' batch '$work/up.txt' --out '$work/inside' 2>&1 |
  grep -q 'up.txt:2: output name ../x.npz has a .... part' && test ! -e '$work/x.npz'"
check "an absolute list output is refused with its line" bash -c "'$sdfgen' batch '$work/abs.txt' --out '$work/inside' 2>&1 |
  grep -q 'abs.txt:1: output name /abs/x.npz is an absolute path'"

# Symbolic links in a folder: a loop (and a second one) ends, each mesh is baked once.
mkdir -p "$work/loops/a/b"
cp "$work/meshes/tet.obj" "$work/loops/a/b/tet.obj"
cp "$work/meshes/octahedron.obj" "$work/loops/octahedron.obj"
ln -s .. "$work/loops/a/b/up"
ln -s ../.. "$work/loops/a/b/top"
timeout 60 "$sdfgen" batch "$work/loops" --out "$work/loops-out" --format sdf --res 8 --status "$work/loops.jsonl" >/dev/null 2>&1
rc=$?
check "a folder with link loops finishes (got $rc)" test $rc -eq 0
check "each mesh of a folder with link loops is baked once" json_check "$work/loops.jsonl" '
sorted(l["output"].split("/loops-out/")[1] for l in lines) == ["a/b/tet.sdf", "octahedron.sdf"] and all(l["status"] == "done" for l in lines)'

# Warnings reach the status lines and the JSON: two zero-area triangles are dropped.
mkdir -p "$work/warned"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 1 2\nf 2 3 3\n' >"$work/warned/degenerate.obj"
"$sdfgen" batch "$work/warned" --out "$work/warned-out" --format sdf --res 8 --status "$work/warned.jsonl" >"$work/warned.txt" 2>&1
check "batch prints a mesh's warnings under its status line" grep -qE '^  warning: .*degenerate.obj: dropped 2 zero-area triangles$' "$work/warned.txt"
check "batch records a mesh's warnings in its JSON line" json_check "$work/warned.jsonl" '
len(lines) == 1 and lines[0]["status"] == "done" and len(lines[0]["warnings"]) == 1 and lines[0]["warnings"][0].endswith("degenerate.obj: dropped 2 zero-area triangles")'
check "every status line has a warnings list" json_check "$work/status.jsonl" 'all(l["warnings"] == [] for l in lines)'

# --band: each mesh baked in a narrow band, as `sdfgen bake --band` bakes it; sparse in .npz and .vdb,
# dense in .sdf; the band in every status line and in the summary.
for format in npz vdb sdf; do
  "$sdfgen" batch "$work/meshes" --out "$work/band-$format" --format $format --res 20 --band 2 --status "$work/band-$format.jsonl" >"$work/band-$format.txt" 2>&1
  check "batch --band 2 --format $format records the band and bakes every good mesh" json_check "$work/band-$format.jsonl" '
len(lines) == 6 and all(l["band"] == 2 for l in lines) and sorted(l["status"] for l in lines) == ["done"] * 4 + ["failed"] * 2'
  check "batch --band 2 --format $format gives sdfgen bake --band 2's field" bash -c "
    '$sdfgen' bake '$work/meshes/sub/open.obj' -o '$work/band-ref.$format' --res 20 --band 2 >/dev/null &&
    '$sdfgen' compare '$work/band-ref.$format' '$work/band-$format/sub/open.$format' | grep -q 'max 0 '"
  check "the summary of batch --band names the band" grep -qE '^batch summary: .*, band 2 voxels, ' "$work/band-$format.txt"
done
check "batch --band --format npz writes sparse archives" $python -c "
import numpy as np, sys
z = np.load(sys.argv[1])
assert 'sdf' not in z.files and z['brick_origins'].shape[1] == 3 and z['brick_values'].shape[:3] == (8, 8, 8)" "$work/band-npz/octahedron.npz"
check "a dense batch records no band" json_check "$work/status.jsonl" 'all(l["band"] is None for l in lines)'
check "batch --band 0.5 is refused before any work" bash -c "
  ! '$sdfgen' batch '$work/meshes' --out '$work/band-half' --band 0.5 >'$work/band-half.txt' 2>&1 &&
  grep -q 'band must be 0 (a dense field) or a finite number of voxels from 1 to 1000000000 (got 0.5)' '$work/band-half.txt' && test ! -e '$work/band-half'"
check "batch --band with --format samples is a one-line error" bash -c "
  ! '$sdfgen' batch '$work/meshes' --out '$work/band-samples' --format samples --band 2 2>'$work/band-samples.txt' &&
  grep -q 'band' '$work/band-samples.txt' && test \$(wc -l <'$work/band-samples.txt') -eq 1 && test ! -e '$work/band-samples'"

check_summary batch
