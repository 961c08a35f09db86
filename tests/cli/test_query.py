"""`sdfgen query` end to end: at a baked field's sample positions the signed distances equal the
field's values exactly; float32 and Fortran-ordered points work; bad point files are one-line errors.
Usage: test_query.py SDFGEN SOURCE_DIR   (exit 77 when numpy is missing)"""
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
except ImportError:
    print("query test: skipped (python3-numpy is not installed)")
    sys.exit(77)

sdfgen, source = sys.argv[1], sys.argv[2]
bunny = os.path.join(source, "assets", "bunny.obj")


def run(*args, ok=True):
    result = subprocess.run([sdfgen, *args], capture_output=True, text=True)
    if ok and result.returncode != 0:
        sys.exit(f"query test: {' '.join(args)} failed: {result.stderr}")
    if not ok and result.returncode == 0:
        sys.exit(f"query test: {' '.join(args)} should have failed")
    return result


with tempfile.TemporaryDirectory() as work:
    field_path = os.path.join(work, "bunny.npz")
    run("bake", bunny, "-o", field_path, "--res", "20")
    field = np.load(field_path)
    sdf, origin, h = field["sdf"], field["origin"], float(field["voxel_size"])
    idx = np.stack(np.meshgrid(*[np.arange(n) for n in sdf.shape], indexing="ij"), axis=-1).reshape(-1, 3)
    points = origin + (idx + 0.5) * h
    np.save(os.path.join(work, "p.npy"), points)
    run("query", bunny, os.path.join(work, "p.npy"), "-o", os.path.join(work, "d.npy"))
    d = np.load(os.path.join(work, "d.npy"))
    expected = sdf[idx[:, 0], idx[:, 1], idx[:, 2]]
    if d.dtype != np.float32 or d.shape != (len(points),) or not np.array_equal(d, expected):
        sys.exit(f"query test: {np.count_nonzero(d != expected)} of {len(d)} distances differ from the field")
    # Fortran order and float32 points read the same points (to float32 precision).
    np.save(os.path.join(work, "f.npy"), np.asfortranarray(points.astype(np.float32)))
    run("query", bunny, os.path.join(work, "f.npy"), "-o", os.path.join(work, "u.npy"), "--what", "unsigned")
    u = np.load(os.path.join(work, "u.npy"))
    if np.max(np.abs(u - np.abs(expected))) > 1e-5:
        sys.exit("query test: float32 Fortran-ordered points give other distances")
    run("query", bunny, os.path.join(work, "p.npy"), "-o", os.path.join(work, "c.npy"), "--what", "closest")
    c = np.load(os.path.join(work, "c.npy"))
    if c.shape != (len(points), 3) or np.max(np.abs(np.linalg.norm(c - points, axis=1) - np.abs(expected))) > 1e-5:
        sys.exit("query test: closest points are not at the distance")
    np.save(os.path.join(work, "bad.npy"), np.zeros((4, 2)))
    message = run("query", bunny, os.path.join(work, "bad.npy"), "-o", os.path.join(work, "x.npy"), ok=False).stderr
    if "bad.npy: points must be an (N, 3) array" not in message:
        sys.exit(f"query test: unexpected message {message!r}")
    if os.path.exists(os.path.join(work, "x.npy")):
        sys.exit("query test: a failed query wrote its output")
print(f"query test: passed ({len(points)} points equal the field)")
