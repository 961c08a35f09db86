#!/usr/bin/env bash
# The Python package as pip users get it: a copy of the source tree installed into a fresh venv
# (`pip install --no-build-isolation`, numpy and torch from the system's site-packages), then
# `import sdfgen, sdfgen.torch` from another folder, the plugin libraries included; then a wheel
# (`pip wheel`) installed into a second venv and used with the source copy gone.
# Usage: test_pip_install.sh SOURCE_DIR   (exit 77: no python3 venv or pip to test with)
set -euo pipefail
source=$(cd "$1" && pwd)
python=/usr/bin/python3
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fail() { echo "pip install test: $*" >&2; exit 1; }

"$python" -m venv --system-site-packages "$scratch/venv" >/dev/null 2>&1 || { echo "no python3 venv (Debian: python3-venv)"; exit 77; }
"$scratch/venv/bin/python" -m pip --version >/dev/null 2>&1 || { echo "no pip in the venv (Debian: python3-pip)"; exit 77; }

# The sources as a clone has them: git's files when this is a checkout, else the tree without build folders.
mkdir "$scratch/src"
if git -C "$source" rev-parse --show-toplevel >/dev/null 2>&1; then
  (cd "$source" && git ls-files -z --cached --others --exclude-standard | tar -c --null -T - --ignore-failed-read -f - 2>/dev/null) \
    | tar -x -C "$scratch/src"
else
  tar -c -C "$source" --exclude='./build*' -f - . | tar -x -C "$scratch/src"
fi

pip() { env -u PYTHONPATH "$1" -m pip "${@:2}" --no-build-isolation --no-index --disable-pip-version-check; }
start=$SECONDS
pip "$scratch/venv/bin/python" install "$scratch/src" >"$scratch/install.log" 2>&1 || { tail -40 "$scratch/install.log"; fail "pip install failed"; }
echo "pip install: $((SECONDS - start)) s"

# From elsewhere, with nothing of the source or build tree on the path.
cat >"$scratch/use.py" <<'PY'
import os, sys
import numpy as np
import sdfgen
assert "torch" not in sys.modules, "importing sdfgen imported torch"
assert os.path.realpath(sdfgen.__file__).startswith(os.path.realpath(sys.prefix)), sdfgen.__file__
here = os.getcwd()
with open("tetra.stl", "w") as out:  # Assimp's plugin, beside libsdfgen in the package
    out.write("solid t\n")
    for a, b, c in [((0, 0, 0), (0, 1, 0), (1, 0, 0)), ((0, 0, 0), (1, 0, 0), (0, 0, 1)),
                    ((0, 0, 0), (0, 0, 1), (0, 1, 0)), ((1, 0, 0), (0, 1, 0), (0, 0, 1))]:
        out.write("facet normal 0 0 0\nouter loop\n" + "".join("vertex %g %g %g\n" % v for v in (a, b, c)) + "endloop\nendfacet\n")
    out.write("endsolid t\n")
mesh = sdfgen.Mesh.load("tetra.stl")
assert mesh.triangle_count == 4
assert mesh.signed_distance(np.array([[0.1, 0.1, 0.1]]))[0] < 0
sdfgen.bake(mesh, res=8).save("tetra.vdb")  # OpenVDB's plugin
assert sdfgen.load_field("tetra.vdb").dims == (8, 8, 8)
try:
    import torch
except ImportError:
    print("torch is not installed: sdfgen.torch not tried")
else:
    import sdfgen.torch
    points = torch.tensor([[0.1, 0.1, 0.1], [2.0, 0.0, 0.0]], dtype=torch.float64, requires_grad=True)
    distance = sdfgen.torch.signed_distance(points, mesh)
    distance.sum().backward()
    assert distance[0] < 0 < distance[1] and torch.allclose(points.grad[1], torch.tensor([1.0, 0, 0], dtype=torch.float64))
print("sdfgen", sdfgen.__version__, "from", os.path.dirname(sdfgen.__file__))
PY
mkdir "$scratch/elsewhere"
(cd "$scratch/elsewhere" && env -u PYTHONPATH "$scratch/venv/bin/python" "$scratch/use.py") || fail "the installed package does not work"

# A wheel, installed into another venv, used with the source copy (and its build folder) gone.
start=$SECONDS
pip "$scratch/venv/bin/python" wheel --no-deps -w "$scratch/wheels" "$scratch/src" >"$scratch/wheel.log" 2>&1 \
  || { tail -40 "$scratch/wheel.log"; fail "pip wheel failed"; }
echo "pip wheel: $((SECONDS - start)) s"
rm -rf "$scratch/src"
"$python" -m venv --system-site-packages "$scratch/other" >/dev/null
pip "$scratch/other/bin/python" install "$scratch"/wheels/sdfgen-*.whl >"$scratch/wheel-install.log" 2>&1 \
  || { cat "$scratch/wheel-install.log"; fail "installing the wheel failed"; }
rm -rf "$scratch/elsewhere"/* && (cd "$scratch/elsewhere" && env -u PYTHONPATH "$scratch/other/bin/python" "$scratch/use.py") \
  || fail "the package installed from the wheel does not work"
echo "pip install test: passed"
