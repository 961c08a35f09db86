"""The corpus of messy meshes (bench/messy_meshes.py: open parts, inside-out and nested parts,
duplicates, thin double-sided panels, interpenetrating parts) baked end to end, each class at
about 1,500 triangles: the winding sign equal sample by sample to the brute-force reference (every
triangle's solid angle summed in double) and distances within 1e-5 voxel of it; every sign
method's bake and the band bake the same on 1 and 2 threads; signed point queries at the samples
equal to the baked field bit for bit.
Usage: test_messy.py SDFGEN SOURCE_DIR   (exit 77 when numpy is missing)"""
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
except ImportError:
    print("messy-mesh test: skipped (python3-numpy is not installed)")
    sys.exit(77)

sdfgen, source = sys.argv[1], sys.argv[2]


def run(*args):
    result = subprocess.run([sdfgen, *args], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"messy-mesh test: sdfgen {' '.join(args)} failed: {result.stderr}")
    return result


with tempfile.TemporaryDirectory() as work:
    subprocess.run(["/usr/bin/python3", os.path.join(source, "bench", "messy_meshes.py"), work, "--triangles", "1500", "--seed", "3"],
                   check=True, capture_output=True)
    classes = sorted(f[:-4] for f in os.listdir(work) if f.endswith(".obj"))
    if len(classes) != 5:
        sys.exit(f"messy-mesh test: the generator wrote {classes}")
    for name in classes:
        mesh = os.path.join(work, name + ".obj")
        out = lambda tag: os.path.join(work, f"{name}-{tag}")
        run("bake", mesh, "--res", "30", "--sign", "winding", "--threads", "1", "-o", out("winding.npz"))
        run("bake", mesh, "--res", "30", "--sign", "winding", "--threads", "2", "-o", out("winding2.npz"))
        run("bake", mesh, "--res", "30", "--method", "brute", "-o", out("brute.npz"))
        winding, brute = np.load(out("winding.npz")), np.load(out("brute.npz"))
        a, b, h = winding["sdf"], brute["sdf"], float(winding["voxel_size"])
        if not np.array_equal(a, np.load(out("winding2.npz"))["sdf"]):
            sys.exit(f"messy-mesh test: {name}: the winding bake differs between 1 and 2 threads")
        wrong = np.count_nonzero(np.signbit(a) != np.signbit(b))
        if wrong:
            sys.exit(f"messy-mesh test: {name}: {wrong} of {a.size} signs differ from the brute-force winding number")
        error = float(np.max(np.abs(np.abs(a) - np.abs(b)))) / h
        if error > 1e-5:
            sys.exit(f"messy-mesh test: {name}: distances differ from brute force by {error} voxels")
        inside = np.count_nonzero(a < 0)
        for sign in ("auto", "pseudonormal", "rays"):
            run("bake", mesh, "--res", "24", "--sign", sign, "--threads", "1", "-o", out(sign + "1.npy"))
            run("bake", mesh, "--res", "24", "--sign", sign, "--threads", "2", "-o", out(sign + "2.npy"))
            if not np.array_equal(np.load(out(sign + "1.npy")), np.load(out(sign + "2.npy"))):
                sys.exit(f"messy-mesh test: {name}: sign {sign} differs between 1 and 2 threads")
        band = []
        for threads in ("1", "2"):
            run("bake", mesh, "--res", "40", "--band", "2", "--threads", threads, "-o", out(f"band{threads}.npz"))
            band.append(np.load(out(f"band{threads}.npz")))
        if band[0].files != band[1].files or not all(np.array_equal(band[0][k], band[1][k]) for k in band[0].files):
            sys.exit(f"messy-mesh test: {name}: the band bake differs between 1 and 2 threads")
        idx = np.stack(np.meshgrid(*[np.arange(n) for n in a.shape], indexing="ij"), axis=-1).reshape(-1, 3)
        np.save(out("points.npy"), winding["origin"] + (idx + 0.5) * h)
        run("query", mesh, out("points.npy"), "--sign", "winding", "-o", out("query.npy"))
        if not np.array_equal(np.load(out("query.npy")), a[idx[:, 0], idx[:, 1], idx[:, 2]]):
            sys.exit(f"messy-mesh test: {name}: signed queries differ from the baked field")
        print(f"messy-mesh test: {name}: {a.size} samples ({inside} inside) equal to brute force; threads and queries agree")
print("messy-mesh test: passed")
