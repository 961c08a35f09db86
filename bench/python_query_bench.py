#!/usr/bin/python3
"""Signed point queries against unsigned ones from Python, near the surface:
    PYTHONPATH=build/python /usr/bin/python3 bench/python_query_bench.py [MESH ...] [--points 1000000] [--rounds 7] [--threads 0]
Draws the points as build/bench/bench_query does (a random point of a random triangle, moved along
its normal by up to 1% of the mesh's diagonal), then times sdfgen.Mesh.signed_distance (the winding
sign) against Mesh.unsigned_distance, and sdfgen.torch's signed_distance against its
unsigned_distance (no gradients kept), the four calls alternating, and prints each call's best of
the rounds (wall seconds) and the two ratios signed / unsigned. The mesh's tree, topology and fans
are built by one untimed call of each first. Default mesh: ../shared/meshes/stanford-bunny.obj
beside the repository, else assets/bunny.obj."""
import argparse
import os
import time

import numpy as np

import sdfgen

here = os.path.dirname(os.path.abspath(__file__))
shared = os.path.join(here, "..", "..", "shared", "meshes", "stanford-bunny.obj")
parser = argparse.ArgumentParser()
parser.add_argument("meshes", nargs="*", default=[shared if os.path.exists(shared) else os.path.join(here, "..", "assets", "bunny.obj")])
parser.add_argument("--points", type=int, default=1_000_000)
parser.add_argument("--rounds", type=int, default=7)
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()
try:
    import torch
    import sdfgen.torch
except ImportError:
    torch = None


def near_surface(mesh, count, rng):
    vertices, faces = np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces)
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    chosen = rng.integers(0, len(faces), count)
    u, v = rng.uniform(size=count), rng.uniform(size=count)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    normal = np.cross(b - a, c - a)[chosen]
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    diagonal = np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0))
    return (a[chosen] + u[:, None] * (b - a)[chosen] + v[:, None] * (c - a)[chosen]
            + normal * rng.uniform(-1, 1, (count, 1)) * 0.01 * diagonal)


for path in args.meshes:
    mesh = sdfgen.Mesh.load(path, threads=args.threads)
    points = near_surface(mesh, args.points, np.random.default_rng(7))
    calls = {"numpy signed": lambda: mesh.signed_distance(points, threads=args.threads),
             "numpy unsigned": lambda: mesh.unsigned_distance(points, threads=args.threads)}
    if torch is not None:
        tensor = torch.from_numpy(points)
        calls["torch signed"] = lambda: sdfgen.torch.signed_distance(tensor, mesh, threads=args.threads)
        calls["torch unsigned"] = lambda: sdfgen.torch.unsigned_distance(tensor, mesh, threads=args.threads)
    for call in calls.values():
        call()  # builds what the queries need, untimed
    best = {name: float("inf") for name in calls}
    for _ in range(args.rounds):
        for name, call in calls.items():
            start = time.perf_counter()
            call()
            best[name] = min(best[name], time.perf_counter() - start)
    line = ", ".join(f"{name} {seconds:.3f} s" for name, seconds in best.items())
    ratios = "; ".join(f"{kind} {best[kind + ' signed'] / best[kind + ' unsigned']:.2f}"
                       for kind in ("numpy", "torch") if kind + " signed" in best)
    print(f"{path}: {mesh.triangle_count} triangles, {args.points} points near the surface, best of {args.rounds}: {line}; signed / unsigned: {ratios}")
