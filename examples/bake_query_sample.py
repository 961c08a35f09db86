#!/usr/bin/python3
"""Bake a field, query points, draw DeepSDF-style samples and save them, with the sdfgen module.

    PYTHONPATH=build/python /usr/bin/python3 examples/bake_query_sample.py [MESH] [OUT_FOLDER]
"""
import os
import sys
import time

import numpy as np

import sdfgen

here = os.path.dirname(os.path.abspath(__file__))
mesh_path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "assets", "bunny.obj")
out = sys.argv[2] if len(sys.argv) > 2 else "out"
os.makedirs(out, exist_ok=True)

mesh = sdfgen.Mesh.load(mesh_path)  # loads and builds the distance tree once
print(mesh, "check:", mesh.check()["description"])

# A 64^3-ish grid; values[i, j, k] is the sample at field.positions()[i, j, k].
field = sdfgen.bake(mesh, res=64, padding=0.1, progress=lambda f: print(f"\rbaking {f:4.0%}", end=""))
print(f"\n{field}: origin {field.origin}, voxel {field.voxel_size:.4g}, sign {field.sign}")
field.save(os.path.join(out, "field.npz"))  # or .npy, .vdb, .nrrd, .sdf

# Point queries: signed and unsigned distances, closest surface points, winding numbers.
lo, hi = (np.array(b) for b in mesh.bounds)
points = np.random.default_rng(0).uniform(lo, hi, size=(100_000, 3))
start = time.perf_counter()
sdf = mesh.signed_distance(points)
print(f"{len(points)} signed distances in {time.perf_counter() - start:.3f} s; {np.mean(sdf < 0):.1%} inside")
closest = mesh.closest_points(points[:5])
print("closest surface points of the first 5:", np.round(closest, 4).tolist())

# The grid's own positions give back exactly the baked values.
assert np.array_equal(mesh.signed_distance(field.positions()), field.values)

# DeepSDF-style training samples, reproducible for a seed.
points, sdf = sdfgen.sample(mesh, 250_000, seed=0)
np.savez(os.path.join(out, "samples.npz"), points=points, sdf=sdf)
print(f"{len(sdf)} samples, {np.mean(np.abs(sdf) < 0.01 * np.max(hi - lo)):.0%} within 1% of the size of the surface -> {out}/samples.npz")
