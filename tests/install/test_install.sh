#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then a separate project built against it with
# find_package(sdfgen CONFIG), and the installed binary run from a copy of the prefix elsewhere
# (nothing of the build tree on its paths).
# Usage: test_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
source=$2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fail() { echo "install test: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$scratch/prefix" >"$scratch/install.log" || { cat "$scratch/install.log"; fail "cmake --install failed"; }
for f in bin/sdfgen include/sdfgen/sdfgen.hpp include/sdfgen/model.hpp lib/cmake/sdfgen/sdfgenConfig.cmake share/sdfgen/assets/bunny.obj; do
  [ -e "$scratch/prefix/$f" ] || fail "not installed: $f"
done
ls "$scratch/prefix"/lib/libsdfgen.so* >/dev/null 2>&1 || fail "libsdfgen.so not installed"
if grep -rq -- "-march=native\|fsanitize" "$scratch/prefix/lib"*/cmake/sdfgen/ 2>/dev/null; then fail "private flags leaked into the package"; fi

cmake -S "$source/tests/install/consumer" -B "$scratch/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$scratch/prefix" >"$scratch/configure.log" 2>&1 \
  || { cat "$scratch/configure.log"; fail "configuring the consumer failed"; }
cmake --build "$scratch/consumer" >"$scratch/build.log" 2>&1 || { cat "$scratch/build.log"; fail "building the consumer failed"; }
out=$("$scratch/consumer/consumer" "$source/assets/bunny.obj" "$scratch/field.sdf") || fail "consumer failed: $out"
echo "$out"
case "$out" in *"3674 triangles"*"sign pseudonormal, distance at the centre -"*) ;; *) fail "unexpected consumer output: $out" ;; esac
[ -s "$scratch/field.sdf" ] || fail "consumer wrote no field"

# The installed binary, moved away from where it was installed: bakes its bundled model, also
# into a .vdb and from an STL, through the OpenVDB and Assimp libraries it opens beside the core.
mv "$scratch/prefix" "$scratch/moved"
"$scratch/moved/bin/sdfgen" bake "$scratch/moved/share/sdfgen/assets/bunny.obj" -o "$scratch/moved.sdf" --res 12 >/dev/null \
  || fail "installed sdfgen bake failed"
cat >"$scratch/tetra.stl" <<'STL'
solid tetra
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 1 0
vertex 1 0 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 0 1
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 0 1
vertex 0 1 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 1 0 0
vertex 0 1 0
vertex 0 0 1
endloop
endfacet
endsolid tetra
STL
"$scratch/moved/bin/sdfgen" bake "$scratch/tetra.stl" -o "$scratch/moved.vdb" --res 12 >/dev/null \
  || fail "installed sdfgen bake of an STL to .vdb failed"
# The Python package, when this build has it: imported from the moved prefix, it finds the
# installed libsdfgen (and through it the plugins) relative to itself.
package=$(find "$scratch/moved" -path '*/sdfgen/__init__.py' -print -quit)
if [ -n "$package" ]; then
  (cd "$scratch" && PYTHONPATH=$(dirname "$(dirname "$package")") /usr/bin/python3 -c "
import numpy as np, sdfgen
assert sdfgen.__file__ == '$package', sdfgen.__file__
mesh = sdfgen.Mesh.load('$scratch/tetra.stl')
sdfgen.bake(mesh, res=8).save('$scratch/python.vdb')
print('installed Python package: signed distance at the centre', mesh.signed_distance(np.array([[0.2, 0.2, 0.2]]))[0])
") || fail "the installed Python package does not work from the moved prefix"
fi
if ! "$scratch/moved/bin/sdfgen" --help | grep -q "built without the viewer"; then
  [ -e "$scratch/moved/share/sdfgen/shaders/fullscreen.vert" ] || fail "shaders not installed"
  SDFGEN_SHADER_DIR= "$scratch/moved/bin/sdfgen" render "$scratch/moved/share/sdfgen/assets/bunny.obj" -o "$scratch/moved.png" --size 64x48 >/dev/null \
    || fail "installed sdfgen render failed"
fi
echo "install test: passed"
