#!/usr/bin/python3
"""The cost of a vertex-optimisation step in sdfgen.torch (vertices that require grad, moved every step):
    PYTHONPATH=build/python /usr/bin/python3 bench/python_refit_bench.py [--levels 5 | --mesh MESH] [--points 10000]
        [--steps 20] [--threads 0] [--no-afresh]
A step is signed_distance (sign auto) at fixed points and its backward pass. Three steps alternate:
on an sdfgen.Mesh built once (the bar: no mesh work per step), on the vertices and faces as tensors
(the tree refit and the sign decision kept, Mesh.with_vertices), and the same with the mesh built
afresh every step (sdfgen.torch's kept meshes set aside: what every step cost before); the refit
steps form one chain, each refitting the previous refit step's mesh. Prints the
median wall-clock and CPU (all threads) milliseconds per step of each and their ratios to the first.
--no-afresh leaves the third out, so that the two compared run back to back (steadier on a loaded
machine).
The icosphere is tests/python/test_refit.py's."""
import argparse
import os
import statistics
import sys
import time

import numpy as np
import torch

import sdfgen
import sdfgen.torch as st

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "python"))
from test_refit import icosphere  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--levels", type=int, default=5, help="the icosphere's subdivisions: 20 * 4^levels triangles")
parser.add_argument("--mesh", help="a mesh file instead of the icosphere")
parser.add_argument("--points", type=int, default=10_000)
parser.add_argument("--steps", type=int, default=20)
parser.add_argument("--threads", type=int, default=0)
parser.add_argument("--no-afresh", action="store_true", help="alternate the first two steps only")
args = parser.parse_args()

if args.mesh:
    loaded = sdfgen.Mesh.load(args.mesh)
    vertices, faces, name = loaded.vertices, loaded.faces, args.mesh
else:
    vertices, faces = icosphere(args.levels)
    name = f"icosphere, {args.levels} levels"
lo, hi = vertices.min(axis=0), vertices.max(axis=0)
pad = 0.1 * np.max(hi - lo)
points = torch.from_numpy(np.random.default_rng(0).uniform(lo - pad, hi + pad, size=(args.points, 3)))
f = torch.from_numpy(faces)
size = np.max(hi - lo)
print(f"{name}: {len(faces)} triangles, {len(vertices)} vertices; {args.points} points; threads {args.threads or os.cpu_count()}")


def moved(step):
    """The vertices of `step`: a small smooth motion, a new position for every vertex."""
    x, y, z = (vertices - lo).T / size
    return vertices + 1e-3 * size * step * np.stack([np.sin(3 * y), np.cos(2 * z), np.sin(x + y)], axis=1)


built_once = sdfgen.Mesh(vertices, faces, threads=args.threads)


def on_built_mesh(step):
    p = points.clone().requires_grad_()
    st.signed_distance(p, built_once, threads=args.threads).sum().backward()


refit_chain = []  # sdfgen.torch's kept meshes of the refit steps: each refits the previous refit's mesh, as in a training loop


def on_tensors(step, afresh):
    v = torch.from_numpy(moved(step)).requires_grad_()
    p = points.clone().requires_grad_()
    # The afresh steps run with nothing kept, and leave the refit chain's meshes as they were.
    st._tensor_meshes[:] = [] if afresh else refit_chain
    st.signed_distance(p, v, f, threads=args.threads).sum().backward()
    if not afresh:
        refit_chain[:] = st._tensor_meshes


steps = {"Mesh built once (points)": on_built_mesh,
         "tensors, tree refit": lambda step: on_tensors(step, afresh=False),
         "tensors, built afresh": lambda step: on_tensors(step, afresh=True)}
if args.no_afresh:
    del steps["tensors, built afresh"]
for run in steps.values():  # warm-up: the first build, the sign decision
    run(0)
wall = {label: [] for label in steps}
cpu = {label: [] for label in steps}  # all threads: steadier than wall-clock on a loaded machine
for step in range(1, args.steps + 1):
    for label, run in steps.items():
        start, start_cpu = time.perf_counter(), time.process_time()
        run(step)
        wall[label].append(time.perf_counter() - start)
        cpu[label].append(time.process_time() - start_cpu)
base = statistics.median(wall["Mesh built once (points)"])
base_cpu = statistics.median(cpu["Mesh built once (points)"])
print(f"  {'median per step':<28} {'wall ms':>8} {'ratio':>6} {'CPU ms':>8} {'ratio':>6}")
for label in steps:
    w, c = statistics.median(wall[label]), statistics.median(cpu[label])
    print(f"  {label:<28} {w * 1e3:8.2f} {w / base:5.2f}x {c * 1e3:8.2f} {c / base_cpu:5.2f}x")
