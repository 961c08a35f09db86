#!/usr/bin/python3
"""B meshes in one sdfgen.torch call against B single calls:
    PYTHONPATH=build/python /usr/bin/python3 bench/python_batch_bench.py [--meshes 16] [--levels 3] [--points 1000]
        [--steps 20] [--threads 0]
B icospheres (tests/python/test_refit.py's, 20 * 4^levels triangles), each scaled and moved
differently, with their own points. Two kinds of step, each timed both ways, alternating:
- a vertex-optimisation step: (B, V, 3) vertices requiring grad, moved every step, with shared
  faces; signed_distance (sign auto) at each mesh's points and the backward pass, as one batched
  call or as B single calls (each refitting its mesh, as the batch does);
- queries on B sdfgen.Mesh built once: signed_distance at each mesh's points, as one call over the
  list or as B single calls.
Prints the median wall-clock and CPU (all threads) milliseconds of each and the single calls'
ratio to the batched call; checks that the two give the same values."""
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
parser.add_argument("--meshes", type=int, default=16, help="B, the meshes in a batch")
parser.add_argument("--levels", type=int, default=3, help="each icosphere's subdivisions: 20 * 4^levels triangles")
parser.add_argument("--points", type=int, default=1000, help="points per mesh")
parser.add_argument("--steps", type=int, default=20)
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()

vertices, faces = icosphere(args.levels)
rng = np.random.default_rng(0)
scales, offsets = rng.uniform(0.8, 1.2, args.meshes), rng.uniform(-0.2, 0.2, (args.meshes, 3))
base = np.stack([vertices * s + o for s, o in zip(scales, offsets)])
points = torch.from_numpy(np.stack([rng.uniform(o - 1.3 * s, o + 1.3 * s, (args.points, 3)) for s, o in zip(scales, offsets)]))
f = torch.from_numpy(faces)
meshes = [sdfgen.Mesh(v, faces) for v in base]
print(f"{args.meshes} icospheres of {len(faces)} triangles, {args.points} points each; threads {args.threads or os.cpu_count()}")


def moved(step):
    """(B, V, 3) vertices of `step`: every vertex of every mesh moved a little."""
    return torch.from_numpy(base * (1 + 1e-3 * step * np.sin(3 * base[..., 1:2])))


def optimisation_step(step, batched):
    v, p = moved(step).requires_grad_(), points.clone().requires_grad_()
    if batched:
        distance = st.signed_distance(p, v, f, threads=args.threads)
    else:
        distance = torch.stack([st.signed_distance(p[b], v[b], f, threads=args.threads) for b in range(args.meshes)])
    distance.sum().backward()
    return distance.detach()


def queries(step, batched):
    p = list(points.unbind(0))
    if batched:
        return torch.stack(st.signed_distance(p, meshes, threads=args.threads))
    return torch.stack([st.signed_distance(p[b], meshes[b], threads=args.threads) for b in range(args.meshes)])


kinds = {"optimisation step (B, V, 3)": optimisation_step, "queries on B Meshes": queries}
for run in kinds.values():  # warm-up: the first builds, the sign decisions; both ways agree
    assert torch.equal(run(0, True), run(0, False))
times = {(kind, batched): ([], []) for kind in kinds for batched in (True, False)}
for step in range(1, args.steps + 1):
    for kind, run in kinds.items():
        for batched in (True, False):
            start, start_cpu = time.perf_counter(), time.process_time()
            run(step, batched)
            wall, cpu = times[(kind, batched)]
            wall.append(time.perf_counter() - start)
            cpu.append(time.process_time() - start_cpu)
print(f"  {'median per call':<30} {'batched ms':>10} {'CPU ms':>8} {'B singles ms':>12} {'CPU ms':>8} {'ratio':>6} {'CPU':>6}")
for kind in kinds:
    (bw, bc), (sw, sc) = ([statistics.median(x) for x in times[(kind, batched)]] for batched in (True, False))
    print(f"  {kind:<30} {bw * 1e3:10.2f} {bc * 1e3:8.2f} {sw * 1e3:12.2f} {sc * 1e3:8.2f} {sw / bw:5.2f}x {sc / bc:5.2f}x")
