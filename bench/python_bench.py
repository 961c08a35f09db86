#!/usr/bin/python3
"""Python point queries and sampling throughput:
    PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py [MESH] [--points 1000000] [--samples 500000] [--threads 0]
Prints the settings and, for each call, seconds and points (or samples) per second."""
import argparse
import os
import time

import numpy as np

import sdfgen

here = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("mesh", nargs="?", default=os.path.join(here, "..", "..", "shared", "meshes", "stanford-bunny.obj"))  # ../shared beside the repo
parser.add_argument("--points", type=int, default=1_000_000)
parser.add_argument("--samples", type=int, default=500_000)
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()

start = time.perf_counter()
mesh = sdfgen.Mesh.load(args.mesh, threads=args.threads)
print(f"{args.mesh}: {mesh.triangle_count} triangles, load + tree {time.perf_counter() - start:.3f} s, threads {args.threads or os.cpu_count()}")
lo, hi = (np.array(b) for b in mesh.bounds)
pad = 0.1 * np.max(hi - lo)
points = np.random.default_rng(0).uniform(lo - pad, hi + pad, size=(args.points, 3))
print(f"{args.points} uniform random points in the bounding box padded by 10%")
mesh.check(threads=args.threads)  # the sign decision is cached; not part of the query times


def timed(name, call, count):
    start = time.perf_counter()
    call()
    seconds = time.perf_counter() - start
    print(f"  {name:<22} {seconds:7.3f} s  {count / seconds / 1e6:6.3f} M/s")


timed("signed_distance", lambda: mesh.signed_distance(points, threads=args.threads), args.points)
timed("unsigned_distance", lambda: mesh.unsigned_distance(points, threads=args.threads), args.points)
timed("closest_points", lambda: mesh.closest_points(points, threads=args.threads), args.points)
timed("winding_number", lambda: mesh.winding_number(points, threads=args.threads), args.points)
timed(f"sample (n={args.samples})", lambda: sdfgen.sample(mesh, args.samples, threads=args.threads), args.samples)
