#!/usr/bin/env bash
# End-to-end checks of the sdfgen command line: usage: test_cli.sh SDFGEN_BINARY REPO_ROOT
set -u
sdfgen=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0

# expect CODE PATTERN -- COMMAND...: the command exits with CODE (or any non-zero for "fail")
# and its combined output matches the extended regex PATTERN.
expect() {
  local code=$1 pattern=$2
  shift 3
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if { [ "$code" = fail ] && [ $rc -ne 0 ]; } || [ "$code" = "$rc" ]; then
    if grep -qE -- "$pattern" <<<"$out"; then
      passed=$((passed + 1))
      return
    fi
  fi
  failed=$((failed + 1))
  echo "FAILED: $* (exit $rc, wanted $code, pattern '$pattern')"
  echo "$out" | sed 's/^/    /' | head -20
}

bunny=$root/assets/bunny.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/tet.obj"

expect 0 'bake' -- "$sdfgen" --help
for option in --res --rays --padding --threads --output --device; do
  expect 0 "$option" -- "$sdfgen" bake --help
done
expect 0 'voxels/s' -- "$sdfgen" bake "$work/tet.obj" -o "$work/tet.sdf" --res 8 --rays 16
expect 0 '^sdfgen-text 1$' -- head -1 "$work/tet.sdf"
expect 0 '^method exact sign=auto/pseudonormal res=8 padding=0.1$' -- sed -n 6p "$work/tet.sdf"
# On a pipe: the summary line alone, no progress bar.
expect 0 '^[^[]*4 triangles, 8x8x8 voxels, method rays \(16 rays\), sign rays, [0-9]+ threads, [0-9.]+ s, [0-9]+ voxels/s$' -- \
  "$sdfgen" bake "$work/tet.obj" -o "$work/tet.sdf" --res 8 --rays 16 --method rays
expect 0 '^method rays rays=16 sign=rays res=8 padding=0.1$' -- sed -n 6p "$work/tet.sdf"
expect 0 'sign: auto chose pseudonormal' -- "$sdfgen" bake "$work/tet.obj" -o "$work/tet.sdf" --res 8
# An open mesh (the tetrahedron without its base): auto falls back to the winding number.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/open.obj"
expect 0 'mesh check: 3 boundary edges' -- "$sdfgen" bake "$work/open.obj" -o "$work/open.sdf" --res 8
expect 0 'auto chose winding: the mesh has holes' -- "$sdfgen" bake "$work/open.obj" -o "$work/open.sdf" --res 8
expect 0 'method brute, sign winding' -- "$sdfgen" bake "$work/tet.obj" -o "$work/brute.sdf" --res 8 --method brute
expect 0 'signs differ: 0 samples' -- "$sdfgen" compare "$work/brute.sdf" "$work/tet.sdf"
expect 0 'max [0-9.e-]+ \([0-9.e-]+ voxels\)' -- "$sdfgen" compare "$work/brute.sdf" "$work/tet.sdf" --band 1
expect 0 'voxels/s' -- "$sdfgen" bake "$work/tet.obj" -o "$work/coarse.sdf" --res 6
expect 1 'different grids' -- "$sdfgen" compare "$work/brute.sdf" "$work/coarse.sdf"
expect 1 "$work/missing.sdf: cannot open" -- "$sdfgen" compare "$work/brute.sdf" "$work/missing.sdf"
expect fail 'sign' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --sign sideways
expect fail 'method' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --method magic
expect fail 'device' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --device abacus
expect 1 'brute method signs by the exact winding number' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --method brute --sign rays
expect 0 '1 threads' -- "$sdfgen" bake "$bunny" -o "$work/bunny.sdf" --res 16 --rays 8 --threads 1
expect 0 'voxels/s' -- "$sdfgen" bench "$work/tet.obj" --res 8 --rays 8

# Bad arguments: clear message, non-zero exit.
expect fail 'res.*0' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --res 0
expect fail 'rays' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --rays 0
expect fail 'padding' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --padding -1
expect fail 'threads' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --threads -2
expect fail 'frobnicate' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --frobnicate
expect fail 'output' -- "$sdfgen" bake "$work/tet.obj"
# No command opens the viewer; without a display that is one line and a failure, never a GLFW error.
expect fail '^sdfgen: no display \(DISPLAY and WAYLAND_DISPLAY are unset\)' -- env -u DISPLAY -u WAYLAND_DISPLAY "$sdfgen"
expect fail '^sdfgen: no display' -- env -u DISPLAY -u WAYLAND_DISPLAY "$sdfgen" view "$work/tet.obj"
# render: bad arguments are one-line errors before any OpenGL context is made.
expect fail "^sdfgen: unknown view 'bogus'" -- "$sdfgen" render "$work/tet.obj" --view mesh,bogus -o "$work/x.png"
expect fail "^sdfgen: --size \(WIDTHxHEIGHT\) '12' is not valid" -- "$sdfgen" render "$work/tet.obj" --size 12 -o "$work/x.png"
expect fail "^sdfgen: --camera \(yaw,pitch,zoom\) '1,2' is not valid" -- "$sdfgen" render "$work/tet.obj" --camera 1,2 -o "$work/x.png"
expect fail '^sdfgen: --slice-axis must be x, y or z' -- "$sdfgen" render "$work/tet.obj" --slice-axis w -o "$work/x.png"
# Bad input files: one line naming the file, exit 1, nothing written.
expect 1 "^sdfgen: $work/missing.obj: cannot open" -- "$sdfgen" bake "$work/missing.obj" -o "$work/x.sdf"
printf 'v 0 0 0\nv 1 0 0\nl 1 2\n' >"$work/lines.obj"
expect 1 "lines.obj: no triangles" -- "$sdfgen" bake "$work/lines.obj" -o "$work/x.sdf"
printf 'v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$work/nan.obj"
expect 1 "nan.obj:1: .*not a finite number" -- "$sdfgen" bake "$work/nan.obj" -o "$work/x.sdf"
expect 1 "grid .* needs .* MiB" -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --res 60000
expect fail '' -- test -e "$work/x.sdf"
expect 1 "$work/nodir/x.sdf: cannot create" -- "$sdfgen" bake "$work/tet.obj" -o "$work/nodir/x.sdf" --res 4

echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
