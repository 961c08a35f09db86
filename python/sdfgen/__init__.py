"""sdfgen: exact signed distance fields, point queries and DeepSDF-style samples from triangle meshes.

Meshes (Mesh.load, Mesh(vertices, faces)), bakes (bake, load_field), point queries (the Mesh's
methods) and samples (sample) take and give numpy arrays; sdfgen.torch gives the same queries on
torch tensors, with gradients (``import sdfgen.torch``; importing sdfgen alone never loads torch).
"""
from ._sdfgen import Error, Field, Mesh, __version__, bake, load_field, sample

# The classes as users name them (the compiled module is an implementation detail).
for _public in (Error, Field, Mesh):
    _public.__module__ = __name__
del _public

__all__ = ["Error", "Field", "Mesh", "__version__", "bake", "load_field", "sample"]
