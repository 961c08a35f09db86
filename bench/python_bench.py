#!/usr/bin/python3
"""Python point queries and sampling throughput:
    PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py [MESH] [--points 1000000] [--samples 500000] [--threads 0]
        [--torch-repeats 5] [--small-calls 5]
Prints the settings and, for each call, seconds and points (or samples) per second; then 1,000 calls
of 100 points against one call of the same 100,000 points (the per-call overhead). Then, when torch
is installed, sdfgen.torch.signed_distance on the same points (forward with gradients kept, and the
backward pass) against the numpy call and Open3D's RaycastingScene.compute_signed_distance (when
python3-open3d is installed and passes a closed-box check: inside negative, outside positive, rays
that hit): the calls alternate, repeated, and the medians are compared."""
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
parser.add_argument("--torch-repeats", type=int, default=5, help="rounds of the alternating torch comparison (0: skip it)")
parser.add_argument("--small-calls", type=int, default=5, metavar="ROUNDS",
                    help="rounds of 1,000 calls of 100 points against one call of 100,000 (0: skip it)")
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

if args.small_calls > 0:
    # Many small calls (a training loop's batches) against one large one with the same points:
    # the per-call overhead, best of the rounds (the calls alternate, so load affects both alike).
    rng = np.random.default_rng(1)
    large = rng.uniform(lo - pad, hi + pad, size=(100_000, 3))
    batches = large.reshape(1000, 100, 3)
    best_small, best_large = float("inf"), float("inf")
    for _ in range(args.small_calls):
        start = time.perf_counter()
        for batch in batches:
            mesh.signed_distance(batch, threads=args.threads)
        best_small = min(best_small, time.perf_counter() - start)
        start = time.perf_counter()
        mesh.signed_distance(large, threads=args.threads)
        best_large = min(best_large, time.perf_counter() - start)
    ratio = best_small / best_large
    print(f"small calls, best of {args.small_calls}: 1,000 x signed_distance(100 points) {best_small:.4f} s"
          f" ({best_small * 1e3:.0f} µs a call), 1 x signed_distance(100,000 points) {best_large:.4f} s:"
          f" {ratio:.2f}x ({'within' if ratio <= 2 else 'OVER'} 2x)")

try:
    import torch
    import sdfgen.torch
except ImportError:
    torch = None
if torch is None or args.torch_repeats <= 0:
    raise SystemExit(0)


def closed_box_check(name, signed_distance, ray_distances=None):
    """A peer enters the comparison only if it passes this sanity check on a closed unit box [0, 1]^3
    (12 outward triangles): negative inside, positive outside, distances right, and rays from
    outside that hit the box where they should. Prints what failed; returns whether it passed."""
    box_points = np.array([[0.5, 0.5, 0.5], [0.5, 0.5, 0.9], [2.0, 0.5, 0.5], [0.5, -0.25, 0.5]])
    expected = np.array([-0.5, -0.1, 1.0, 0.25])
    rays = np.array([[0.5, 0.5, -1.0, 0, 0, 1], [3.0, 0.25, 0.75, -1, 0, 0]])  # origin, direction: hits at 1 and 2
    failures = []
    got = np.asarray(signed_distance(box_points), dtype=np.float64)
    if not np.allclose(got, expected, atol=1e-5):
        failures.append(f"signed distances {np.round(got, 4).tolist()} at the centre, inside, outside, outside "
                        f"(expected {expected.tolist()})")
    hits = np.asarray(ray_distances(rays), dtype=np.float64) if ray_distances else np.array([1.0, 2.0])
    if not np.allclose(hits, [1.0, 2.0], atol=1e-5):
        failures.append(f"rays from outside hit at {hits.tolist()} (expected [1.0, 2.0])")
    print(f"  closed-box check of {name}: " + ("passed" if not failures else "FAILED, left out of the comparison: " + "; ".join(failures)))
    return not failures


try:
    import open3d as o3d
except ImportError:
    o3d = None
if o3d:
    def open3d_scene(vertices, faces):
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.core.Tensor(np.asarray(vertices, dtype=np.float32)), o3d.core.Tensor(np.asarray(faces, dtype=np.uint32)))
        return scene
    corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=np.float64)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    box_faces = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    box = sdfgen.Mesh(corners, box_faces, name="unit box")
    closed_box_check("sdfgen", box.signed_distance)  # the check's own expectations, on sdfgen's distances
    box_scene = open3d_scene(corners, box_faces)
    if closed_box_check(f"Open3D {o3d.__version__}",
                        lambda q: box_scene.compute_signed_distance(o3d.core.Tensor(q.astype(np.float32))).numpy(),
                        lambda r: box_scene.cast_rays(o3d.core.Tensor(r.astype(np.float32)))["t_hit"].numpy()):
        scene = open3d_scene(mesh.vertices, mesh.faces)
        open3d_points = o3d.core.Tensor(points.astype(np.float32))
    else:
        o3d = None

print(f"sdfgen.torch against numpy{' and Open3D ' + o3d.__version__ if o3d else ''}: medians of {args.torch_repeats} alternating rounds,"
      " wall-clock and CPU seconds (all threads; steadier on a busy machine)")
wall, cpu = {}, {}
def record(name, call):
    start, start_cpu = time.perf_counter(), time.process_time()
    result = call()
    wall.setdefault(name, []).append(time.perf_counter() - start)
    cpu.setdefault(name, []).append(time.process_time() - start_cpu)
    return result

tensor = torch.from_numpy(points)
for _ in range(args.torch_repeats):
    reference = record("numpy signed_distance", lambda: mesh.signed_distance(points, threads=args.threads))
    queried = tensor.clone().requires_grad_(True)
    distance = record("torch forward", lambda: sdfgen.torch.signed_distance(queried, mesh, threads=args.threads))
    record("torch backward", lambda: distance.sum().backward())
    record("torch forward, no grad", lambda: sdfgen.torch.signed_distance(tensor, mesh, threads=args.threads))
    if o3d:
        theirs = record("Open3D signed distance", lambda: scene.compute_signed_distance(open3d_points).numpy())
assert np.array_equal(distance.detach().numpy().astype(np.float32), reference)
median_wall = {name: float(np.median(times)) for name, times in wall.items()}
median_cpu = {name: float(np.median(times)) for name, times in cpu.items()}
for name in median_wall:
    print(f"  {name:<24} {median_wall[name]:7.3f} s  {args.points / median_wall[name] / 1e6:6.3f} M/s   CPU {median_cpu[name]:7.3f} s")
for label, median in (("wall", median_wall), ("CPU", median_cpu)):
    line = (f"  {label}: torch forward / numpy {median['torch forward'] / median['numpy signed_distance']:.2f}x"
            f" (no grad {median['torch forward, no grad'] / median['numpy signed_distance']:.2f}x),"
            f" backward / forward {median['torch backward'] / median['torch forward']:.3f}x")
    if o3d:
        line += f", Open3D / torch forward {median['Open3D signed distance'] / median['torch forward']:.2f}x"
    print(line)
if o3d:
    wrong = int(np.count_nonzero(np.signbit(theirs) != np.signbit(reference)))
    print(f"  Open3D signs that differ from sdfgen's: {wrong} of {args.points} ({100 * wrong / args.points:.1f}%)")
