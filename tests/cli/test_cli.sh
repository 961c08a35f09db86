#!/usr/bin/env bash
# End-to-end checks of the sdfgen command line: usage: test_cli.sh SDFGEN_BINARY REPO_ROOT
set -u
sdfgen=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/../support/check.sh"

bunny=$root/assets/bunny.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/tet.obj"

expect 0 'bake' -- "$sdfgen" --help
for option in --res --rays --padding --threads --output; do
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
# A band field whose dims multiply to 2^64 (each axis below 2^31): refused on reading, never
# compared as "0 of 0 samples" (the count wrapped to 0) or crashed on.
if /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
  /usr/bin/python3 - "$work/wrap.npz" <<'PY'
import sys, numpy as np
np.savez(sys.argv[1], brick_origins=np.zeros((0, 3), np.int32), brick_values=np.zeros((8, 8, 8, 0), np.float32, order="F"),
         inside_boxes=np.zeros((0, 6), np.int32), background=np.float32(1.5), dims=np.array([4194304, 2097152, 2097152]),
         origin=np.zeros(3), voxel_size=np.float64(1e-6), method=np.array("exact"), source=np.array("wrap"))
PY
  expect 1 "^sdfgen: $work/wrap.npz: grid 4194304x2097152x2097152 has more than 2\\^58 samples$" -- "$sdfgen" compare "$work/wrap.npz" "$work/wrap.npz"
  expect 1 "^sdfgen: $work/wrap.npz: grid 4194304x2097152x2097152 has more than 2\\^58 samples$" -- "$sdfgen" surface "$work/wrap.npz" -o "$work/x.obj"
fi
expect fail 'sign' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --sign sideways
expect fail 'method' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --method magic
expect 1 '^sdfgen: --sign: method brute signs by the exact winding number; sign rays does not apply$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --method brute --sign rays
expect 0 '1 threads' -- "$sdfgen" bake "$bunny" -o "$work/bunny.sdf" --res 16 --rays 8 --threads 1
expect 0 'voxels/s' -- "$sdfgen" bench "$work/tet.obj" --res 8 --rays 8

# Bad arguments: clear message, non-zero exit. The bake settings' limits are the core's one check
# (sdfgen::problem, the same for the viewer and Python), named by option, for every command that bakes.
expect 1 '^sdfgen: --res: res must be from 1 to 65536 voxels along the longest side \(got 0\)$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --res 0
expect 1 '^sdfgen: --rays: rays must be from 1 to 65536 per sample \(got 0\)$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --rays 0
expect 1 '^sdfgen: --rays: rays must be from 1 to 65536 per sample \(got 100000000\)$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --rays 100000000 --method rays
expect 1 '^sdfgen: --padding: padding must be a finite number from 0 to 100 \(got -1\)$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --padding -1
expect 1 '^sdfgen: --res: res must be from 1 to 65536' -- "$sdfgen" bench "$work/tet.obj" --res 65537
expect 1 '^sdfgen: --res: res must be from 1 to 65536' -- "$sdfgen" surface "$work/tet.obj" -o "$work/x.obj" --res 65537
expect 1 '^sdfgen: --band: band must be 0 \(a dense field\) or a finite number of voxels from 1 to 1000000000 \(got 0.5\)$' -- \
  "$sdfgen" batch "$work/tet.obj" --out "$work/never" --band 0.5
vexpect 1 '^sdfgen: --rays: rays must be from 1 to 65536' -- "$sdfgen" render "$work/tet.obj" -o "$work/x.png" --rays 65537
expect fail 'threads' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --threads -2
expect fail 'frobnicate' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --frobnicate
expect fail 'output' -- "$sdfgen" bake "$work/tet.obj"
# Builds without the viewer (-DSDFGEN_VIEWER=OFF) have no view or render command: vexpect runs a
# check only where the viewer is built.
has_viewer=0
"$sdfgen" --help | grep -q '^  render' && has_viewer=1
vexpect() { [ "$has_viewer" = 1 ] || return 0; expect "$@"; }
[ "$has_viewer" = 1 ] || expect fail 'built without the viewer' -- "$sdfgen"
# No command opens the viewer; without a display that is one line and a failure, never a GLFW error.
vexpect fail '^sdfgen: no display \(DISPLAY and WAYLAND_DISPLAY are unset\)' -- env -u DISPLAY -u WAYLAND_DISPLAY "$sdfgen"
vexpect fail '^sdfgen: no display' -- env -u DISPLAY -u WAYLAND_DISPLAY "$sdfgen" view "$work/tet.obj"
# `sdfgen MESH...` is the viewer on those meshes (what a file manager's "open with" runs).
vexpect fail '^sdfgen: no display' -- env -u DISPLAY -u WAYLAND_DISPLAY "$sdfgen" "$work/tet.obj" "$work/tet.obj"
# Several meshes bake their union; the field's source names them all.
printf 'v 2 0 0\nv 3 0 0\nv 2 1 0\nv 2 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/tet2.obj"
expect 0 'tet.obj\+tet2.obj -> .*: 8 triangles' -- "$sdfgen" bake "$work/tet.obj" "$work/tet2.obj" -o "$work/union.sdf" --res 16
expect 0 '^source tet.obj\+tet2.obj$' -- sed -n 2p "$work/union.sdf"
# render draws each mesh of a scene in its own colour: seen from the front, the left tetrahedron
# orange (red over blue), the right one blue.
if [ "$has_viewer" = 1 ] && command -v python3 >/dev/null; then
  env ASAN_OPTIONS=detect_leaks=0 "$sdfgen" render "$work/tet.obj" "$work/tet2.obj" --view mesh --camera 0,0,1 --size 96x48 \
    --background 0,0,0 -o "$work/two.png" >/dev/null 2>&1
  expect 0 '^left red, right blue$' -- python3 - "$work/two.png" <<'PY'
import struct, sys, zlib
png = open(sys.argv[1], "rb").read()
chunks, at = {}, 8
while at < len(png):
    size, kind = struct.unpack(">I4s", png[at:at + 8])
    chunks[kind] = chunks.get(kind, b"") + png[at + 8:at + 8 + size]
    at += 12 + size
width, height, depth, colour = struct.unpack(">IIBB", chunks[b"IHDR"][:10])
assert (depth, colour) == (8, 6), "expected 8-bit RGBA"
raw, rows, stride = zlib.decompress(chunks[b"IDAT"]), [], width * 4
previous = bytearray(stride)
for y in range(height):
    kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a, b, c = line[i - 4] if i >= 4 else 0, previous[i], previous[i - 4] if i >= 4 else 0
        p = a + b - c
        predictor = [0, a, b, (a + b) // 2, a if abs(p - a) <= min(abs(p - b), abs(p - c)) else b if abs(p - b) <= abs(p - c) else c][kind]
        line[i] = (line[i] + predictor) & 255
    rows.append(line)
    previous = line
def redder(x0, x1):
    votes = [px[x * 4] - px[x * 4 + 2] for px in rows for x in range(x0, x1) if max(px[x * 4:x * 4 + 3]) > 20]
    return sum(v > 0 for v in votes) > 0.9 * len(votes) > 20, sum(v < 0 for v in votes) > 0.9 * len(votes) > 20
left, right = redder(0, width // 2), redder(width // 2, width)
print(("left red" if left[0] else "left not red") + ", " + ("right blue" if right[1] else "right not blue"))
PY
fi
# A field made from another mesh: render says so on stderr and still draws. (Mesa's OSMesa leaks
# at exit, so the sanitizer build's leak check is off for this one drawing command.)
vexpect 0 "^sdfgen: warning: $work/tet.sdf: the field was made from $work/tet.obj, not from bunny.obj, and its grid does not cover the model" -- \
  env ASAN_OPTIONS=detect_leaks=0 "$sdfgen" render "$bunny" --sdf "$work/tet.sdf" --view slice --size 32x24 -o "$work/mismatch.png"
# render: bad arguments are one-line errors before any OpenGL context is made.
vexpect fail "^sdfgen: unknown view 'bogus'" -- "$sdfgen" render "$work/tet.obj" --view mesh,bogus -o "$work/x.png"
vexpect fail "^sdfgen: --size \(WIDTHxHEIGHT\) '12' is not valid" -- "$sdfgen" render "$work/tet.obj" --size 12 -o "$work/x.png"
vexpect fail "^sdfgen: --camera \(yaw,pitch,zoom\) '1,2' is not valid" -- "$sdfgen" render "$work/tet.obj" --camera 1,2 -o "$work/x.png"
vexpect fail '^sdfgen: --slice-axis must be x, y or z' -- "$sdfgen" render "$work/tet.obj" --slice-axis w -o "$work/x.png"
vexpect fail '^sdfgen: --slice-normal must not be zero' -- "$sdfgen" render "$work/tet.obj" --slice-normal 0,0,0 -o "$work/x.png"
vexpect fail '^sdfgen: --colormap must be diverging, viridis or grey' -- "$sdfgen" render "$work/tet.obj" --colormap jet -o "$work/x.png"
# Bad input files: one line naming the file, exit 1, nothing written.
expect 1 "^sdfgen: $work/missing.obj: cannot open" -- "$sdfgen" bake "$work/missing.obj" -o "$work/x.sdf"
printf 'v 0 0 0\nv 1 0 0\nl 1 2\n' >"$work/lines.obj"
expect 1 "lines.obj: no triangles" -- "$sdfgen" bake "$work/lines.obj" -o "$work/x.sdf"
printf 'v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$work/nan.obj"
expect 1 "nan.obj:1: .*not a finite number" -- "$sdfgen" bake "$work/nan.obj" -o "$work/x.sdf"
expect 1 "grid .* needs .* MiB" -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --res 60000
expect fail '' -- test -e "$work/x.sdf"
expect 1 "$work/nodir/x.sdf: cannot create" -- "$sdfgen" bake "$work/tet.obj" -o "$work/nodir/x.sdf" --res 4

# Formats by extension: every one bakes, compares equal to the text file, and renders' loader reads it.
for ext in npy npz vdb nrrd; do
  expect 0 "tet.obj -> $work/tet.$ext" -- "$sdfgen" bake "$work/tet.obj" -o "$work/tet.$ext" --res 8
done
expect 0 'voxels/s' -- "$sdfgen" bake "$work/tet.obj" -o "$work/tet.sdf" --res 8
for ext in npz vdb nrrd; do
  expect 0 'max 0 \(0 voxels\).*' -- "$sdfgen" compare "$work/tet.sdf" "$work/tet.$ext"
done
expect 0 'voxels/s' -- "$sdfgen" bake "$work/tet.obj" -o "$work/band.vdb" --res 8 --band 2
expect 0 'band: 2 voxels each side' -- "$sdfgen" bake "$work/tet.obj" -o "$work/band.npy" --res 8 --band 2
# render shows a band field file from its bricks and says how.
vexpect 0 "^$work/band.vdb: band field [0-9]+x[0-9]+x[0-9]+ \(band 2 voxels\): shown at full resolution$" -- \
  env ASAN_OPTIONS=detect_leaks=0 "$sdfgen" render "$work/tet.obj" --sdf "$work/band.vdb" --view slice,raymarch --size 32x24 -o "$work/band.png"
expect 1 '^sdfgen: --band: band must be 0 \(a dense field\) or a finite number of voxels from 1 to 1000000000 \(got 0.5\)$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/band.npy" --res 8 --band 0.5
expect 1 '^sdfgen: --method: a band bake measures exact distances; method rays makes dense fields only$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/band.npy" --res 8 --band 2 --method rays
expect 1 '^sdfgen: --band with --channels applies to .vdb output only' -- "$sdfgen" bake "$work/tet.obj" -o "$work/band.npz" --res 8 --band 2 --channels gradient
expect 1 "x.xyz: unknown field format '.xyz'; known: .sdf, .npy, .npz, .vdb, .nrrd" -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.xyz" --res 4
expect fail '' -- test -e "$work/x.xyz"
# Channels beside the distance: into .npz and .vdb; refused up front, in one line naming the way
# out, for formats that hold the distance only, for methods that find no nearest triangle, and
# for unknown names.
expect 0 '^channels: sdf,gradient,closest,triangle$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/ch.npz" --res 8 --channels sdf,gradient,closest,triangle
expect 0 'max 0 \(0 voxels\).*' -- "$sdfgen" compare "$work/tet.sdf" "$work/ch.npz"
expect 0 '^channels: sdf,triangle$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/ch.vdb" --res 8 --channels triangle --band 2
for ext in sdf npy nrrd; do
  expect 1 "^sdfgen: $work/ch.$ext: .$ext holds the distance \(sdf\) only; for channels gradient write .npz or .vdb$" -- \
    "$sdfgen" bake "$work/tet.obj" -o "$work/ch.$ext" --res 8 --channels gradient
  expect fail '' -- test -e "$work/ch.$ext"
done
expect 1 "^sdfgen: --channels: channels closest come from the exact method's nearest triangles; method rays gives the distance \\(sdf\\) only$" -- \
  "$sdfgen" bake "$work/tet.obj" -o "$work/x.npz" --res 8 --channels closest --method rays
expect 1 "^sdfgen: unknown channel 'normals' \(expected a comma-separated list of sdf, gradient, closest, triangle\)$" -- \
  "$sdfgen" bake "$work/tet.obj" -o "$work/x.npz" --res 8 --channels sdf,normals
# A target that is not a regular file (a pipe) gets the archive written through.
mkfifo "$work/pipe.npz"
timeout 20 cat "$work/pipe.npz" >"$work/piped.npz" &
reader=$!
expect 0 'voxels/s' -- timeout 20 "$sdfgen" bake "$work/tet.obj" -o "$work/pipe.npz" --res 8 --channels gradient
wait $reader
expect 0 'max 0 \(0 voxels\).*' -- "$sdfgen" compare "$work/tet.sdf" "$work/piped.npz"
expect 0 '10 samples' -- "$sdfgen" sample "$work/tet.obj" -n 10 -o "$work/ch-samples.npz" --channels gradient,triangle
expect 1 "^sdfgen: unknown channel 'normals'" -- "$sdfgen" sample "$work/tet.obj" -n 10 -o "$work/x.npz" --channels normals
# Samples are an .npz: any other name is refused before sampling, and nothing is written.
for name in s.vdb s.npy s; do
  expect 1 "^sdfgen: $work/$name: samples are written as .npz only; name the output \*.npz" -- "$sdfgen" sample "$work/tet.obj" -n 10 -o "$work/$name"
  expect 1 '' -- test -e "$work/$name"
done
printf 'not numpy' >"$work/bad.npy"
expect 1 "^sdfgen: $work/bad.npy: not a NumPy .npy file" -- "$sdfgen" compare "$work/bad.npy" "$work/tet.npy"
# Meshes in other formats (assimp-utils writes them when installed).
if command -v assimp >/dev/null; then
  assimp export "$work/tet.obj" "$work/tet.stl" -fstlb >/dev/null 2>&1
  expect 0 '4 triangles' -- "$sdfgen" bake "$work/tet.stl" -o "$work/tet-stl.sdf" --res 8
  expect 0 'max 0 \(0 voxels\)' -- "$sdfgen" compare "$work/tet.sdf" "$work/tet-stl.sdf"
fi
# glTF external files: only from the glTF's folder (SDFGEN_GLTF_FOLDERS allows more); refused in one
# line that quotes the URI, never the outside file's bytes.
if [ -e "$(dirname "$sdfgen")/libsdfgen_assimp.so" ]; then
  mkdir -p "$work/gltf"
  /usr/bin/python3 - "$work" <<'PY'
import base64, json, struct, sys
work = sys.argv[1]
data = struct.pack("<9f3I", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 2)
open(work + "/outside.bin", "wb").write(data)
open(work + "/gltf/inside.bin", "wb").write(data)
def gltf(uri):
    return json.dumps({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
        "buffers": [{"byteLength": 48, "uri": uri}]})
for name, uri in [("inside", "inside.bin"), ("up", "../outside.bin"), ("absolute", "/etc/ld.so.cache")]:
    open(work + "/gltf/" + name + ".gltf", "w").write(gltf(uri))
PY
  expect 0 '1 triangles' -- "$sdfgen" bake "$work/gltf/inside.gltf" -o "$work/x.sdf" --res 4
  expect 1 "^sdfgen: $work/gltf/up.gltf: buffer 0's uri '../outside.bin' leads outside the glTF's folder \(SDFGEN_GLTF_FOLDERS lists more folders to read from\)$" -- \
    "$sdfgen" bake "$work/gltf/up.gltf" -o "$work/x.sdf" --res 4
  expect 0 '1 triangles' -- env SDFGEN_GLTF_FOLDERS="$work" "$sdfgen" bake "$work/gltf/up.gltf" -o "$work/x.sdf" --res 4
  expect 1 "^sdfgen: $work/gltf/absolute.gltf: buffer 0's uri '/etc/ld.so.cache' is an absolute path" -- \
    "$sdfgen" bake "$work/gltf/absolute.gltf" -o "$work/x.sdf" --res 4
  expect 0 'SDFGEN_GLTF_FOLDERS' -- "$sdfgen" bake --help
fi
printf 'solid broken\n facet normal 0 0 1\n' >"$work/broken.stl"
expect 1 "^sdfgen: $work/broken.stl:3: the file ends where 'outer' was expected$" -- "$sdfgen" bake "$work/broken.stl" -o "$work/x.sdf" --res 4
# sdfgen's own readers: PLY triangle strips (-1 between strips) give the same field as the OBJ;
# counts beyond the file, indices past the vertices and 4-corner STL facets are one-line errors;
# skipped faces are warned about.
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n15 0 2 1 -1 0 1 3 -1 0 3 2 -1 1 2 3\n' >"$work/strips.ply"
expect 0 '4 triangles' -- "$sdfgen" bake "$work/strips.ply" -o "$work/strips.sdf" --res 8
expect 0 'max 0 \(0 voxels\)' -- "$sdfgen" compare "$work/tet.sdf" "$work/strips.sdf"
{ printf 'ply\nformat binary_little_endian 1.0\nelement vertex 200000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n'; head -c 300 /dev/zero; } >"$work/huge.ply"
expect 1 "^sdfgen: $work/huge.ply: the header declares 200000000 vertices \(at least 2.4e\+09 bytes\) but only 300 bytes follow it$" -- \
  "$sdfgen" bake "$work/huge.ply" -o "$work/x.sdf" --res 4
printf 'OFF\n4 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n' >"$work/huge.off"
expect 1 "^sdfgen: $work/huge.off: the header declares 2000000000 faces" -- "$sdfgen" bake "$work/huge.off" -o "$work/x.sdf" --res 4
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 4\n' >"$work/index.off"
expect 1 "^sdfgen: $work/index.off:8: face refers to vertex 4 but the file has 4 vertices" -- "$sdfgen" bake "$work/index.off" -o "$work/x.sdf" --res 4
printf 'OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n2 0 1\n' >"$work/short-face.off"
expect 0 "^sdfgen: warning: $work/short-face.off: skipped 1 face of fewer than 3 vertices$" -- "$sdfgen" bake "$work/short-face.off" -o "$work/x.sdf" --res 4
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid x\n' >"$work/four.stl"
expect 1 "^sdfgen: $work/four.stl:7: a facet has more than 3 vertices" -- "$sdfgen" bake "$work/four.stl" -o "$work/x.sdf" --res 4
cp "$work/tet.obj" "$work/tet.xyz"
expect 1 "unknown mesh format '.xyz'" -- "$sdfgen" bake "$work/tet.xyz" -o "$work/x.sdf" --res 4
# surface: a closed manifold mesh from an open one, from a mesh or a saved field.
expect 0 'mesh check of the output: 0 boundary edges, 0 non-manifold edges, 0 inconsistently oriented edges, 0 non-manifold vertices' -- \
  "$sdfgen" surface "$work/open.obj" -o "$work/open-surface.obj" --res 16
expect 0 'triangles' -- "$sdfgen" surface "$work/tet.npz" -o "$work/tet-surface.ply"
expect 0 '^ply$' -- head -1 "$work/tet-surface.ply"
expect 1 'padding' -- "$sdfgen" surface "$work/tet.obj" -o "$work/x.obj" --padding 0
expect 1 "x.stl: unknown surface format" -- "$sdfgen" surface "$work/tet.obj" -o "$work/x.stl" --res 8
# A band field (a .vdb level set): compare takes it by value in its band and by sign outside;
# surface meshes it as the level set it is, closed and manifold; the dense formats hold its dense form.
"$sdfgen" bake "$bunny" -o "$work/bunny-band.vdb" --res 40 --band 2 >/dev/null
"$sdfgen" bake "$bunny" -o "$work/bunny.sdf" --res 40 >/dev/null
expect 0 "^band fields $work/bunny-band.vdb \(\|d\| < [0-9.e-]+, 2 voxels\): values compared where \|d\| is below the band, [0-9]+ samples outside it compared by sign only$" -- \
  "$sdfgen" compare "$work/bunny-band.vdb" "$work/bunny.sdf"
expect 0 '^abs difference: max 0 \(0 voxels\)' -- "$sdfgen" compare "$work/bunny.sdf" "$work/bunny-band.vdb"
expect 0 '^signs differ: 0 samples' -- "$sdfgen" compare "$work/bunny.sdf" "$work/bunny-band.vdb"
expect 0 'grid 40x40x33 \(band field, [0-9]+ bricks\)' -- "$sdfgen" surface "$work/bunny-band.vdb" -o "$work/band-surface.obj"
expect 0 'mesh check of the output: 0 boundary edges, 0 non-manifold edges, 0 inconsistently oriented edges, 0 non-manifold vertices' -- \
  "$sdfgen" surface "$work/bunny-band.vdb" -o "$work/band-surface.obj"
expect 1 "^sdfgen: $work/bunny-band.vdb: iso 1 lies outside the band field's band" -- "$sdfgen" surface "$work/bunny-band.vdb" -o "$work/x.obj" --iso 1
# ---- Issue 8: hostile input, nonsense arguments, files (each failed before the fix) ----------
# OBJ hygiene: a BOM is skipped; hex floats, overflowing or missing vertices, short faces and NULs
# are refused with the line; pipes and FIFOs are read; the input size is bounded.
printf '\xef\xbb\xbf' | cat - "$work/tet.obj" >"$work/bom.obj"
expect 0 '4 triangles' -- "$sdfgen" bake "$work/bom.obj" -o "$work/bom.sdf" --res 4
printf 'v 0x1p0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$work/hex.obj"
expect 1 "hex.obj:1: vertex coordinate '0x1p0' is not a decimal number" -- "$sdfgen" bake "$work/hex.obj" -o "$work/x.sdf"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 2 3 4294967300\n' >"$work/big.obj"
expect 1 "big.obj:5: face refers to vertex 4294967300" -- "$sdfgen" bake "$work/big.obj" -o "$work/x.sdf"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2\n' >"$work/short.obj"
expect 1 "short.obj:6: face has 2 vertices" -- "$sdfgen" bake "$work/short.obj" -o "$work/x.sdf"
{ cat "$work/tet.obj"; printf 'f 1 \0 2 3\n'; } >"$work/nul.obj"
expect 1 "nul.obj:9: NUL byte" -- "$sdfgen" bake "$work/nul.obj" -o "$work/x.sdf"
expect 1 "^sdfgen: /dev/zero:1: NUL byte" -- timeout 10 "$sdfgen" bake /dev/zero -o "$work/x.sdf"
expect 0 '4 triangles' -- sh -c '"$1" bake /dev/stdin -o "$2" --res 4 <"$3"' sh "$sdfgen" "$work/pipe.sdf" "$work/tet.obj"
expect 0 '4 triangles' -- sh -c 'cat "$3" | "$1" bake /dev/stdin -o "$2" --res 4' sh "$sdfgen" "$work/pipe.sdf" "$work/tet.obj"
mkfifo "$work/fifo.obj"
(cat "$work/tet.obj" >"$work/fifo.obj" &)
expect 0 '4 triangles' -- timeout 10 "$sdfgen" bake "$work/fifo.obj" -o "$work/fifo.sdf" --res 4
expect 1 'larger than the input limit of 1 MiB \(set SDFGEN_MAX_INPUT_MB' -- \
  sh -c 'yes "v 0 0 0" | SDFGEN_MAX_INPUT_MB=1 timeout 10 "$1" bake /dev/stdin -o "$2"' sh "$sdfgen" "$work/x.sdf"
head -c 2000000 /dev/zero | tr '\0' '\n' >"$work/blank.obj"
expect 1 'blank.obj: larger than the input limit of 1 MiB' -- env SDFGEN_MAX_INPUT_MB=1 "$sdfgen" bake "$work/blank.obj" -o "$work/x.sdf"
# Field files: the declared size is checked before allocating; the reader refuses what the writer would.
# (250 million samples: a GiB if allocated; the reader must stay under 200 MB of memory.)
printf 'sdfgen-text 1\nsource a\ndims 1000 1000 250\norigin 0 0 0\nvoxel 1\nmethod exact\nvalues\n0\n' >"$work/huge.sdf"
expect 1 'huge.sdf:8: file ends after 1 of 250000000 values' -- "$sdfgen" compare "$work/huge.sdf" "$work/huge.sdf"
expect 0 '^ok$' -- sh -c '/usr/bin/time -f %M -o "$2" "$1" compare "$3" "$3" 2>/dev/null; [ "$(tail -n 1 "$2")" -lt 200000 ] && echo ok' sh \
  "$sdfgen" "$work/rss" "$work/huge.sdf"
field_with() { printf 'sdfgen-text 1\nsource %s\ndims 1 1 1\norigin 0 0 0\nvoxel 1\nmethod %s\nvalues\n0\n' "$1" "$2"; }
field_with a $'exact ke\ty=1' >"$work/tab.sdf"
expect 1 "tab.sdf:6: method parameter" -- "$sdfgen" compare "$work/tab.sdf" "$work/tab.sdf"
field_with a 'exact a=b=c' >"$work/eq.sdf"
expect 1 "eq.sdf:6: method parameter 'a=b=c'" -- "$sdfgen" compare "$work/eq.sdf" "$work/eq.sdf"
field_with $'a\rb' exact >"$work/cr.sdf"
expect 1 "cr.sdf:2: source name has a carriage return" -- "$sdfgen" compare "$work/cr.sdf" "$work/cr.sdf"
expect 1 "^sdfgen: $work: is a directory" -- "$sdfgen" compare "$work" "$work/brute.sdf"
# Nonsense numbers: one-line errors.
vexpect fail "^sdfgen: --camera \(yaw,pitch,zoom\) 'nan,nan,nan' is not valid: 'nan' is not a finite number" -- \
  "$sdfgen" render "$work/tet.obj" --camera nan,nan,nan -o "$work/x.png"
vexpect fail "'inf' is not a finite number" -- "$sdfgen" render "$work/tet.obj" --camera 1,2,inf -o "$work/x.png"
vexpect fail '^sdfgen: --camera zoom must be positive' -- "$sdfgen" render "$work/tet.obj" --camera 1,2,0 -o "$work/x.png"
vexpect fail '^sdfgen: --camera zoom must be positive' -- "$sdfgen" render "$work/tet.obj" --camera 1,2,-1 -o "$work/x.png"
vexpect fail "^--slice-pos: 'nan' is not a finite number" -- "$sdfgen" render "$work/tet.obj" --slice-pos nan -o "$work/x.png"
vexpect fail '^--slice-pos: 2 is not in \[0, 1\]' -- "$sdfgen" render "$work/tet.obj" --slice-pos 2 -o "$work/x.png"
expect fail "^--band: 'nan' is not a finite number" -- "$sdfgen" compare "$work/brute.sdf" "$work/tet.sdf" --band nan
expect fail '^--band: -1 is not in' -- "$sdfgen" compare "$work/brute.sdf" "$work/tet.sdf" --band -1
expect 1 '^sdfgen: --padding: padding must be a finite number from 0 to 100 \(got nan\)$' -- "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --padding nan
vexpect fail "^sdfgen: --size '1e10x5' must be two whole numbers" -- "$sdfgen" render "$work/tet.obj" --size 1e10x5 -o "$work/x.png"
vexpect fail "^sdfgen: --background.*'nan' is not a finite number" -- "$sdfgen" render "$work/tet.obj" --background nan,0,0 -o "$work/x.png"
vexpect fail "^sdfgen: --background '2,0,0': each channel must be in 0..1" -- "$sdfgen" render "$work/tet.obj" --background 2,0,0 -o "$work/x.png"
# Memory: the whole bake's buffers are counted up front (a grid whose field fits at 4 bytes per
# sample but not with the ray field that exact distances signed by rays need beside it, 8 bytes),
# with the figure in the message.
avail_kib=$(awk '/^MemAvailable:/ {print $2}' /proc/meminfo)
res=$(awk -v kib="$avail_kib" 'BEGIN { printf "%d", (kib * 1024 / 6) ^ (1 / 3) }')
expect 1 "^sdfgen: grid ${res}x${res}x${res} \(method exact, sign rays\) needs about [0-9]+ MiB but only [0-9]+ MiB of memory is available" -- \
  timeout 20 "$sdfgen" bake "$work/tet.obj" -o "$work/x.sdf" --res "$res" --padding 0 --sign rays
# Outputs: never the input (also through a symbolic or hard link); written through symlinks;
# modes kept; a failed write leaves the old file and exits non-zero; no temporary left behind.
cp "$work/tet.obj" "$work/keep.obj"
expect 1 "keep.obj: is the input file .*keep.obj; refusing to overwrite it" -- "$sdfgen" bake "$work/keep.obj" -o "$work/keep.obj"
ln -s keep.obj "$work/keep-link.obj"
ln "$work/keep.obj" "$work/keep-hard.obj"
expect 1 "refusing to overwrite it" -- "$sdfgen" bake "$work/keep.obj" -o "$work/keep-link.obj"
expect 1 "refusing to overwrite it" -- "$sdfgen" bake "$work/keep-link.obj" -o "$work/keep-hard.obj"
vexpect 1 "refusing to overwrite it" -- "$sdfgen" render "$work/keep.obj" -o "$work/keep-link.obj"
expect 0 '' -- cmp "$work/tet.obj" "$work/keep.obj"
"$sdfgen" bake "$work/tet.obj" -o "$work/real.sdf" --res 4 >/dev/null
ln -s real.sdf "$work/link.sdf"
expect 0 '4x4x4' -- "$sdfgen" bake "$work/tet.obj" -o "$work/link.sdf" --res 4
expect 0 '' -- test -L "$work/link.sdf"
expect 0 '^dims 4 4 4$' -- sed -n 3p "$work/real.sdf"
chmod 600 "$work/real.sdf"
expect 0 'voxels/s' -- "$sdfgen" bake "$work/tet.obj" -o "$work/real.sdf" --res 5
expect 0 '^600$' -- stat -c %a "$work/real.sdf"
expect 0 '^640$' -- sh -c 'umask 027; "$1" bake "$2" -o "$3" --res 4 >/dev/null && stat -c %a "$3"' sh "$sdfgen" "$work/tet.obj" "$work/umask.sdf"
# The binary formats write through the same atomic writer: through symlinks, modes kept.
for ext in npy npz vdb nrrd; do
  "$sdfgen" bake "$work/tet.obj" -o "$work/real.$ext" --res 4 >/dev/null
  ln -s "real.$ext" "$work/link.$ext"
  chmod 600 "$work/real.$ext"
  expect 0 '5x5x5' -- "$sdfgen" bake "$work/tet.obj" -o "$work/link.$ext" --res 5
  expect 0 '' -- test -L "$work/link.$ext"
  expect 0 '^600$' -- stat -c %a "$work/real.$ext"
done
# A full device (our own node, so that a regression replaces a scratch file and not /dev/full).
if mknod "$work/full-device.sdf" c 1 7 2>/dev/null; then
  expect 1 'full-device.sdf: write failed \(No space left on device\)' -- "$sdfgen" bake "$work/tet.obj" -o "$work/full-device.sdf" --res 4
  expect 0 '' -- test -c "$work/full-device.sdf"
else
  echo "cli: skipped the full-device test (cannot make a device node here)"
fi
# Two bakes to one path at once: both succeed, and the file is one of the two complete outputs.
"$sdfgen" bake "$bunny" -o "$work/one.sdf" --res 24 >/dev/null
"$sdfgen" bake "$bunny" -o "$work/two.sdf" --res 25 >/dev/null
"$sdfgen" bake "$bunny" -o "$work/both.sdf" --res 24 >/dev/null & first=$!
"$sdfgen" bake "$bunny" -o "$work/both.sdf" --res 25 >/dev/null & second=$!
wait $first; first_rc=$?
wait $second; second_rc=$?
expect 0 '' -- test "$first_rc$second_rc" = 00
expect 0 '' -- sh -c 'cmp -s "$1" "$2" || cmp -s "$1" "$3"' sh "$work/both.sdf" "$work/one.sdf" "$work/two.sdf"
# The CPU kernel's SIMD path (core/distance/kernel.hpp): `sdfgen info` names it; forcing the baseline path
# bakes the same field bit for bit; an unknown path is refused.
expect 0 '^CPU kernel: (avx512|avx2|baseline) ' -- "$sdfgen" info
expect 0 '^CPU kernel: baseline ' -- env SDFGEN_SIMD=baseline "$sdfgen" info
expect 0 '' -- env SDFGEN_SIMD=baseline "$sdfgen" bake "$bunny" -o "$work/baseline.sdf" --res 24
expect 0 '' -- cmp "$work/one.sdf" "$work/baseline.sdf"
if grep -qw avx512dq /proc/cpuinfo 2>/dev/null && grep -qw avx512f /proc/cpuinfo; then # the fan kernel's AVX-512 copy
  expect 0 '^CPU kernel: avx512 ' -- env SDFGEN_SIMD=avx512 "$sdfgen" info
  expect 0 '' -- env SDFGEN_SIMD=avx512 "$sdfgen" bake "$bunny" -o "$work/avx512.sdf" --res 24
  expect 0 '' -- cmp "$work/one.sdf" "$work/avx512.sdf"
fi
expect fail '^sdfgen: SDFGEN_SIMD=sse9: ' -- env SDFGEN_SIMD=sse9 "$sdfgen" bake "$bunny" -o "$work/never.sdf" --res 8
# SIGTERM, SIGINT or SIGHUP while the field is written: the temporary file is removed. (A
# background job of a script starts with SIGINT ignored; env gives it back its default action.)
# On a busy machine the save can end before the signal lands; then it is tried again.
for sig in TERM INT HUP; do
  for attempt in 1 2 3; do
    env --default-signal=INT "$sdfgen" bake "$bunny" -o "$work/killed.sdf" --res 128 --method rays --sign rays --rays 1 >/dev/null 2>&1 &
    pid=$!
    for _ in $(seq 1 3000); do compgen -G "$work/killed.sdf.tmp-*" >/dev/null && break; sleep 0.005; done
    kill -s $sig $pid
    wait $pid 2>/dev/null
    rc=$?
    [ $rc -ne 0 ] && break
  done
  expect 0 '' -- test $rc -eq $((128 + $(kill -l $sig)))
  expect 1 '' -- compgen -G "$work/killed.sdf.tmp-*"
done
# Killed by the file-size limit (SIGXFSZ, ulimit -f in KiB) while the field is written: the old
# file stays, and no temporary is left.
"$sdfgen" bake "$work/tet.obj" -o "$work/limited.sdf" --res 8 >/dev/null
cp "$work/limited.sdf" "$work/limited-old.sdf"
(ulimit -c 0; ulimit -f 64; exec "$sdfgen" bake "$bunny" -o "$work/limited.sdf" --res 64 >/dev/null 2>&1)
rc=$?
expect 0 '' -- test $rc -eq $((128 + $(kill -l XFSZ)))
expect 0 '' -- cmp "$work/limited.sdf" "$work/limited-old.sdf"
expect 1 '' -- compgen -G "$work/limited.sdf.tmp-*"
# An output name of 255 bytes (the longest a file name may be): its temporary's name is shortened to fit.
long=$(printf 'n%.0s' $(seq 1 251)).sdf
expect 0 'voxels/s' -- "$sdfgen" bake "$work/tet.obj" -o "$work/$long" --res 8
expect 0 '^sdfgen-text 1$' -- head -1 "$work/$long"
# Standard output on a pipe is written directly (the summary line follows the field), through a
# link that names the format (/dev/stdout there leads to /proc/self/fd/1, a link to "pipe:[N]").
ln -s /dev/stdout "$work/stdout.sdf"
expect 0 '^sdfgen-text 1$' -- bash -c "'$sdfgen' bake '$work/tet.obj' -o '$work/stdout.sdf' --res 8 | head -1"
# A full disk (a 64 KiB tmpfs, where mounting is allowed): the old file stays, exit non-zero.
full=$work/full
mkdir "$full"
if mount -t tmpfs -o size=64k tmpfs "$full" 2>/dev/null; then
  echo old >"$full/f.sdf"
  echo old >"$full/f.png"
  expect 1 "f.sdf: write failed \(No space left on device\)" -- "$sdfgen" bake "$bunny" -o "$full/f.sdf" --res 32
  expect 0 '^old$' -- cat "$full/f.sdf"
  vexpect 1 "f.png: write failed \(No space left on device\)" -- "$sdfgen" render "$bunny" -o "$full/f.png" --size 1024x1024 --view mesh,wire
  expect 0 '^old$' -- cat "$full/f.png"
  expect 0 '^f.png f.sdf $' -- sh -c 'ls "$1" | tr "\n" " "' sh "$full"
  umount "$full"
else
  echo "cli: skipped the full-disk test (cannot mount a tmpfs here)"
fi
# Inside out: every face of the tetrahedron flipped. Auto finds it and fixes the signs; the
# winding sign (|w| > 1/2) needs no fix; an explicit pseudonormal follows the faces, with a warning.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n' >"$work/inside-out.obj"
expect 0 'inside out \(negative volume\)' -- "$sdfgen" bake "$work/inside-out.obj" -o "$work/inside-out.sdf" --res 8
expect 0 'auto chose pseudonormal: .*; the mesh is inside out' -- "$sdfgen" bake "$work/inside-out.obj" -o "$work/inside-out.sdf" --res 8
expect 0 'signs differ: 0 samples' -- "$sdfgen" compare "$work/brute.sdf" "$work/inside-out.sdf"
expect 0 'warning: .*inside-out.obj: the mesh is inside out .*; sign pseudonormal follows the faces' -- \
  "$sdfgen" bake "$work/inside-out.obj" -o "$work/x.sdf" --res 8 --sign pseudonormal
check 'the winding sign warns of no inside-out mesh' sh -c '! "$1" bake "$2" -o "$3" --res 8 --sign winding 2>&1 | grep warning' \
  sh "$sdfgen" "$work/inside-out.obj" "$work/x.sdf"
expect 0 'signs differ: 0 samples' -- "$sdfgen" compare "$work/brute.sdf" "$work/x.sdf"

# Every command refuses an output that is one of its inputs, directly or through a link, before any work.
for link in keep.obj keep-link.obj keep-hard.obj; do
  expect 1 "$link: is the input file .*keep.obj; refusing to overwrite it" -- "$sdfgen" surface "$work/keep.obj" -o "$work/$link" --res 8
  expect 1 "$link: is the input file .*keep.obj; refusing to overwrite it" -- "$sdfgen" sample "$work/keep.obj" -n 10 -o "$work/$link"
done
"$sdfgen" bake "$work/tet.obj" -o "$work/field.sdf" --res 8 >/dev/null
ln -s field.sdf "$work/field-link.obj"
expect 1 "field-link.obj: is the input file .*field.sdf; refusing" -- "$sdfgen" surface "$work/field.sdf" -o "$work/field-link.obj"
expect 1 "refusing to overwrite it" -- "$sdfgen" query "$work/keep.obj" "$work/keep.obj" -o "$work/keep-link.obj"
expect 0 '' -- cmp "$work/tet.obj" "$work/keep.obj"
expect 0 '^dims 8 8 8$' -- sed -n 3p "$work/field.sdf"
# A not-yet-existing output that names an input by another path (dir/../name) is refused too.
expect 1 "refusing to overwrite it" -- "$sdfgen" sample "$work/keep.obj" -n 10 -o "$work/sub/../keep.obj"
# A surface that cannot be a valid mesh (a voxel of 1e300: float positions overflow) is refused
# before the old output is touched.
sed 's/^voxel .*/voxel 1e300/' "$work/field.sdf" >"$work/huge-voxel.sdf"
echo old >"$work/surface-old.obj"
expect 1 "^sdfgen: .*huge-voxel.sdf: " -- "$sdfgen" surface "$work/huge-voxel.sdf" -o "$work/surface-old.obj"
expect 0 '^old$' -- cat "$work/surface-old.obj"
expect 0 'mesh check of the output' -- "$sdfgen" surface "$work/field.sdf" -o "$work/surface-new.obj"
# A mesh far beyond float range: the error names the file and its extent.
printf 'v -1e38 0 0\nv 1e38 0 0\nv 0 1e38 0\nv 0 0 1e38\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/huge.obj"
expect 1 "^sdfgen: .*huge.obj: the mesh is 2e\+38 across; with padding 0.1 its grid would be 2.4e\+38 across" -- \
  "$sdfgen" bake "$work/huge.obj" -o "$work/x.sdf" --res 8

# Numeric options: NaN, infinities and values out of range are refused by every option of every
# command, at parsing (the numeric options are read from each command's --help).
printf 'tet.obj\n' >"$work/list.txt"
declare -A base=(
  [bake]="$work/tet.obj -o $work/never.sdf"
  [render]="$work/tet.obj -o $work/never.png"
  [surface]="$work/tet.obj -o $work/never.obj"
  [query]="$work/tet.obj $work/points.npy -o $work/never.npy"
  [sample]="$work/tet.obj -n 10 -o $work/never.npz"
  [batch]="$work/list.txt --out $work/never"
  [bench]="$work/tet.obj"
  [compare]="$work/field.sdf $work/field.sdf"
)
numeric_options=0
for command in "${!base[@]}"; do
  "$sdfgen" "$command" --help >"$work/help.txt" 2>&1 || continue
  for option in $(grep -oE -- '--[a-z-]+ (INT|UINT|FLOAT)' "$work/help.txt" | cut -d' ' -f1 | sort -u); do
    numeric_options=$((numeric_options + 1))
    for value in nan inf -inf 1e999; do
      # shellcheck disable=SC2086 # the base arguments are words
      expect fail "$option" -- "$sdfgen" "$command" ${base[$command]} "$option=$value"
    done
  done
done
expect 0 '' -- test "$numeric_options" -ge 30
expect 1 '' -- test -e "$work/never.sdf" -o -e "$work/never.npz" -o -e "$work/never.obj" -o -e "$work/never"
for command in bake surface query sample batch bench; do
  expect fail "^--threads: Value 1025 not in range 0 to 1024" -- "$sdfgen" "$command" ${base[$command]} --threads 1025
done
# Seeds are whole numbers in 0..2^64-1: negative and too large ones are refused, not saturated.
expect fail "^--seed: '-1' is not a whole number from 0 to 18446744073709551615" -- "$sdfgen" sample "$work/tet.obj" -n 10 -o "$work/s.npz" --seed -1
expect fail "^--seed: '18446744073709551616' is not a whole number" -- "$sdfgen" sample "$work/tet.obj" -n 10 -o "$work/s.npz" --seed 18446744073709551616
expect fail "^--seed: '1e3' is not a whole number" -- "$sdfgen" sample "$work/tet.obj" -n 10 -o "$work/s.npz" --seed 1e3
expect 0 'seed 18446744073709551615' -- "$sdfgen" sample "$work/tet.obj" -n 10 -o "$work/s.npz" --seed 18446744073709551615
expect fail "^--count: '0' is not a whole number from 1" -- "$sdfgen" sample "$work/tet.obj" -n 0 -o "$work/s.npz"
# 2^34 samples (about 832 GiB at the peak) are refused by the memory check before anything is allocated.
expect 1 "^sdfgen: .*tet.obj: 17179869184 samples need about 851968 MiB but only [0-9]+ MiB of memory is available" -- \
  timeout 20 "$sdfgen" sample "$work/tet.obj" -n 17179869184 -o "$work/s.npz"

# Warnings reach the user from every command: two zero-area triangles are dropped, and said so.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 1 2\nf 2 3 3\n' >"$work/degenerate.obj"
warned='^sdfgen: warning: .*degenerate.obj: dropped 2 zero-area triangles$'
expect 0 "$warned" -- "$sdfgen" bake "$work/degenerate.obj" -o "$work/d.sdf" --res 8
expect 0 "$warned" -- "$sdfgen" surface "$work/degenerate.obj" -o "$work/d.obj" --res 8
expect 0 "$warned" -- "$sdfgen" sample "$work/degenerate.obj" -n 10 -o "$work/d.npz"
expect 0 "$warned" -- "$sdfgen" bench "$work/degenerate.obj" --res 8
vexpect 0 "$warned" -- env ASAN_OPTIONS=detect_leaks=0 "$sdfgen" render "$work/degenerate.obj" --view mesh --size 16x16 -o "$work/d.png"
# (N, 3) float64 points in .npy: one point at the origin.
{ printf '\x93NUMPY\x01\x00\x76\x00'; printf '%-117s\n' "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 3), }"; head -c 24 /dev/zero; } >"$work/origin.npy"
expect 0 "$warned" -- "$sdfgen" query "$work/degenerate.obj" "$work/origin.npy" -o "$work/d.npy"
# A point 1e300 away: refused with the reason (the search cannot answer it exactly), never an inf.
{ printf '\x93NUMPY\x01\x00\x76\x00'; printf '%-117s\n' "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 3), }"
  printf '\x9c\x75\x00\x88\x3c\xe4\x37\x7e'; head -c 16 /dev/zero; } >"$work/far.npy"
expect 1 "^sdfgen: .*tet.obj: query point 0 \(1e\+300, 0, 0\) is 1e\+300 mesh sizes from the mesh's bounding box; points are answered up to 10000 mesh sizes away" -- \
  "$sdfgen" query "$work/tet.obj" "$work/far.npy" -o "$work/far-out.npy"
expect 1 '' -- test -e "$work/far-out.npy"

# ---- Hostile field files: sizes checked before allocating (under a 1 GB address-space cap, so
# that a reader that allocates what a file claims fails the test), one line naming the file --------
# AddressSanitizer reserves terabytes of address space for its shadow memory, so an ASan build
# cannot start under such a cap: there, its allocator refuses any single allocation over 1 GB instead.
address_cap=0
if sh -c 'prlimit --as=1000000000 "$0" --help' "$sdfgen" >/dev/null 2>&1; then
  address_cap=1
  cap() { prlimit --as=1000000000 "$@"; }
else
  cap() { ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}max_allocation_size_mb=1000:allocator_may_return_null=1" "$@"; }
fi
# patch FILE OFFSET HEX...: overwrites bytes in place.
patch() { local file=$1 at=$2; shift 2; printf "$(printf '\\x%s' "$@")" | dd of="$file" bs=1 seek="$at" conv=notrunc status=none; }
offset() { grep -boa -- "$2" "$1" | head -1 | cut -d: -f1; } # offset FILE TEXT: where TEXT first is
"$sdfgen" bake "$work/tet.obj" -o "$work/h.vdb" --res 8 >/dev/null
head -c 200 "$work/h.vdb" >"$work/cut.vdb"
expect 1 "^sdfgen: $work/cut.vdb: not a readable OpenVDB file: .*$" -- cap "$sdfgen" surface "$work/cut.vdb" -o "$work/x.obj"
for keep in 1000 4000 8000 12000; do
  head -c $keep "$work/h.vdb" >"$work/cut.vdb"
  expect 1 "^sdfgen: $work/cut.vdb: not a readable OpenVDB file" -- cap "$sdfgen" compare "$work/cut.vdb" "$work/h.vdb"
done
cp "$work/h.vdb" "$work/dims.vdb" # sdfgen_dims 1000^3 on a grid of 8^3 samples
patch "$work/dims.vdb" $(($(offset "$work/dims.vdb" sdfgen_dims) + 24)) e8 03 00 00 e8 03 00 00 e8 03 00 00
expect 1 "^sdfgen: $work/dims.vdb: sdfgen_dims 1000x1000x1000 says 1000000000 samples, the dense grid holds 512$" -- \
  cap "$sdfgen" surface "$work/dims.vdb" -o "$work/x.obj"
cp "$work/h.vdb" "$work/nan.vdb" # the transform's scale NaN
patch "$work/nan.vdb" $(($(offset "$work/nan.vdb" UniformScaleTranslateMap) + 24)) 00 00 00 00 00 00 f8 7f
expect 1 "^sdfgen: $work/nan.vdb: " -- "$sdfgen" surface "$work/nan.vdb" -o "$work/x.obj"
"$sdfgen" bake "$work/tet.obj" -o "$work/h.npz" --res 8 >/dev/null
cp "$work/h.npz" "$work/claims.npz" # sdf.npy (the first member) claims 4 GB in its local header
patch "$work/claims.npz" 22 80 28 6b ee
expect 1 "^sdfgen: $work/claims.npz: " -- cap "$sdfgen" surface "$work/claims.npz" -o "$work/x.obj"
# A 3.9 MB zip bomb: sdf.npy declares 1000^3 float32 (4 GB) and deflates to 3.9 MB (each MiB of
# zeros after a full flush compresses to the same bytes); within deflate's ratio, refused by memory
# (so only under a real address-space cap: an ASan build has 4 GB to give it).
if [ $address_cap = 1 ] && command -v python3 >/dev/null; then
  python3 - "$work/bomb.npz" <<'PY'
import struct, sys, zlib
head = b"{'descr': '<f4', 'fortran_order': True, 'shape': (1000, 1000, 1000), }"
head = b"\x93NUMPY\x01\x00" + struct.pack("<H", 118) + head.ljust(117) + b"\n"
z = zlib.compressobj(9, zlib.DEFLATED, -15)
data = [z.compress(head) + z.flush(zlib.Z_FULL_FLUSH)]
mib = z.compress(bytes(1 << 20)) + z.flush(zlib.Z_FULL_FLUSH)
data += [mib] * 3814 + [z.compress(bytes(4000000000 - 3814 * (1 << 20))) + z.flush()]
data = b"".join(data)
size, name = len(head) + 4000000000, b"sdf.npy"
local = struct.pack("<4sHHHHHIIIHH", b"PK\x03\x04", 20, 0, 8, 0, 0, 0, len(data), size, len(name), 0) + name
central = struct.pack("<4sHHHHHHIIIHHHHHII", b"PK\x01\x02", 20, 20, 0, 8, 0, 0, 0, len(data), size, len(name), 0, 0, 0, 0, 0, 0) + name
end = struct.pack("<4sHHHHIIH", b"PK\x05\x06", 0, 0, 1, 1, len(central), len(local) + len(data), 0)
open(sys.argv[1], "wb").write(local + data + central + end)
PY
  expect 0 '' -- test "$(stat -c %s "$work/bomb.npz")" -lt 4200000
  expect 1 "^sdfgen: $work/bomb.npz: sdf.npy: (not enough memory|dimensions 1000x1000x1000 too large)" -- cap "$sdfgen" surface "$work/bomb.npz" -o "$work/x.obj"
fi
# A 2 KB band .npz of 1000^3 samples without bricks: compared sparse, counted rather than made
# dense (4 GB); a grid that differs is named before anything is made dense.
if /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
  /usr/bin/python3 - "$work/empty.npz" <<'PY'
import sys, numpy as np
np.savez(sys.argv[1], brick_origins=np.zeros((0, 3), np.int32), brick_values=np.zeros((8, 8, 8, 0), np.float32, order="F"),
         inside_boxes=np.array([[0, 0, 0, 1000, 8, 8]], np.int32), background=np.float32(0.03), dims=np.array([1000, 1000, 1000]),
         origin=np.zeros(3), voxel_size=np.float64(0.01), method=np.array("exact"), source=np.array("empty"))
PY
  expect 0 'signs differ: 0 samples' -- cap "$sdfgen" compare "$work/empty.npz" "$work/empty.npz"
  expect 0 '0 of 1000000000 samples compared' -- cap "$sdfgen" compare "$work/empty.npz" "$work/empty.npz"
  expect 0 ' 1000000000 samples outside it compared by sign only' -- cap "$sdfgen" compare "$work/empty.npz" "$work/empty.npz"
  expect 1 "^sdfgen: $work/empty.npz vs $work/tet.npz: the fields have different grids: 1000x1000x1000 and 8x8x8$" -- \
    cap "$sdfgen" compare "$work/empty.npz" "$work/tet.npz"
  expect 1 "^sdfgen: $work/tet.npz vs $work/empty.npz: the fields have different grids: 8x8x8 and 1000x1000x1000$" -- \
    cap "$sdfgen" compare "$work/tet.npz" "$work/empty.npz"
fi
printf 'sdfgen-text 1\nsource s\ndims 2 2 2\norigin 0 0 0\nvoxel 1e-320\nmethod m\nvalues\n' >"$work/denormal.sdf"
for _ in 1 2 3 4 5 6 7 8; do echo 1 >>"$work/denormal.sdf"; done
expect 1 "^sdfgen: $work/denormal.sdf: voxel size [0-9.e-]+ is not a positive normal float32" -- "$sdfgen" surface "$work/denormal.sdf" -o "$work/x.obj"
sed 's/^voxel .*/voxel 1e300/' "$work/denormal.sdf" >"$work/huge.sdf"
expect 1 "^sdfgen: $work/huge.sdf: voxel size 1e\+300 is not a positive normal float32" -- "$sdfgen" surface "$work/huge.sdf" -o "$work/x.obj"
sed 's/^origin .*/origin 1.7e308 0 0/' "$work/denormal.sdf" | sed 's/^voxel .*/voxel 1/' >"$work/far.sdf"
expect 1 "^sdfgen: $work/far.sdf: grid .* reaches beyond float32's range" -- "$sdfgen" surface "$work/far.sdf" -o "$work/x.obj"
expect fail '' -- test -e "$work/x.obj"
"$sdfgen" bake "$work/tet.obj" -o "$work/h.nrrd" --res 8 >/dev/null
sed '0,/^type: float$/s//type: float\ntype: double/' "$work/h.nrrd" >"$work/twice.nrrd"
expect 1 "^sdfgen: $work/twice.nrrd:4: field 'type' appears twice in the NRRD header$" -- "$sdfgen" surface "$work/twice.nrrd" -o "$work/x.obj"
sed 's/^kinds: domain domain domain$/kinds: RGB-color domain domain/' "$work/h.nrrd" >"$work/rgb.nrrd"
expect 1 "^sdfgen: $work/rgb.nrrd: NRRD kind 'RGB-color' on axis 0 is not a spatial axis" -- "$sdfgen" surface "$work/rgb.nrrd" -o "$work/x.obj"
sed 's/^type: float$/type: fl\x01oa\tt/' "$work/h.nrrd" >"$work/ctl.nrrd"
expect 1 "^sdfgen: $work/ctl.nrrd: NRRD type 'fl\\\\x01oa\\\\tt' is not supported" -- "$sdfgen" surface "$work/ctl.nrrd" -o "$work/x.obj"
# Points whose byte count overflows 64 bits: (2^62, 3) float64.
{ printf '\x93NUMPY\x01\x00\x76\x00'; printf "%-117s\n" "{'descr': '<f8', 'fortran_order': False, 'shape': (4611686018427387904, 3), }"; } >"$work/overflow.npy"
expect 1 "^sdfgen: $work/overflow.npy: shape \(4611686018427387904, 3\) of 8-byte items is more than 2\^64 bytes$" -- \
  "$sdfgen" query "$work/tet.obj" "$work/overflow.npy" -o "$work/x.npy"

echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
