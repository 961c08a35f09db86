"""sdfgen: exact signed distance fields, point queries and DeepSDF-style samples from triangle meshes.

Meshes (Mesh.load, Mesh(vertices, faces)), bakes (bake, load_field: a Field, or a SparseField for
a narrow band), point queries (the Mesh's methods) and samples (sample) take and give numpy arrays; sdfgen.torch gives the same queries on
torch tensors, with gradients (``import sdfgen.torch``; importing sdfgen alone never loads torch).
"""
from . import _sdfgen
from ._sdfgen import *  # noqa: F401,F403 (every public name of the compiled module)
from ._sdfgen import __version__  # noqa: F401

# The classes as users name them (the compiled module is an implementation detail).
for _name in dir(_sdfgen):
    _value = getattr(_sdfgen, _name)
    if isinstance(_value, type) and _value.__module__ == _sdfgen.__name__:
        _value.__module__ = __name__
del _name, _value
