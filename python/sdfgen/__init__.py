"""sdfgen: exact signed distance fields, point queries and DeepSDF-style samples from triangle meshes.

Meshes (Mesh.load, Mesh(vertices, faces)), bakes (bake, load_field: a Field, or a SparseField for
a narrow band), point queries (the Mesh's methods) and samples (sample) take and give numpy arrays; sdfgen.torch gives the same queries on
torch tensors, with gradients (``import sdfgen.torch``; importing sdfgen alone never loads torch).
"""
import glob as _glob
import os as _os

try:
    from . import _sdfgen
except ImportError as _error:
    _here = _os.path.dirname(_os.path.abspath(__file__))
    if _glob.glob(_os.path.join(_here, "_sdfgen*.so")) or _glob.glob(_os.path.join(_here, "_sdfgen*.pyd")):
        raise  # the module is there but does not load: its own message says why
    # Python's own message would blame a circular import.
    raise ImportError(
        f"sdfgen's compiled module (_sdfgen) is missing from {_here}: the package's Python files are laid out but the "
        "module was not built (./run.sh builds only the command line). Build it with "
        "`cmake --build build --target sdfgen_python` (or `scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -- "
        "sdfgen_python`), or install the package with `pip install --no-build-isolation .`", name="sdfgen._sdfgen") from None
from ._sdfgen import *  # noqa: F401,F403 (every public name of the compiled module)
from ._sdfgen import __version__  # noqa: F401

# The classes as users name them (the compiled module is an implementation detail).
for _name in dir(_sdfgen):
    _value = getattr(_sdfgen, _name)
    if isinstance(_value, type) and _value.__module__ == _sdfgen.__name__:
        _value.__module__ = __name__
del _name, _value, _glob, _os
