#!/usr/bin/python3
"""Fields written by `sdfgen bake` read by the programs users read them with: numpy (.npy, .npz),
pyopenvdb (.vdb) or teem's unu (.nrrd), compared with the sdfgen-text file of the same bake.

Usage: python_readers.py numpy|openvdb|teem SDFGEN_BINARY SOURCE_DIR
Exits 77 (ctest's skip code) when numpy, pyopenvdb or teem-unu is not installed.
"""
import os
import shutil
import subprocess
import sys
import tempfile

mode, sdfgen, root = sys.argv[1:4]
try:
    import numpy as np
    if mode == "openvdb":
        import pyopenvdb as vdb
except ImportError as missing:
    print(f"skipped: {missing}")
    sys.exit(77)
if mode == "teem" and not shutil.which("teem-unu"):
    print("skipped: teem-unu (Debian teem-apps) is not installed")
    sys.exit(77)

MESH = os.path.join(root, "assets", "bunny.obj")


def load_text(path):
    with open(path) as f:
        lines = f.read().split("\n")
    assert lines[0] == "sdfgen-text 1" and lines[6] == "values", lines[:7]
    nx, ny, nz = map(int, lines[2].split()[1:])
    values = np.array(lines[7:7 + nx * ny * nz], dtype=np.float32)
    return {
        "source": lines[1][len("source "):],
        "dims": (nx, ny, nz),
        "origin": np.array(lines[3].split()[1:], dtype=np.float64),
        "voxel": float(lines[4].split()[1]),
        "method": lines[5][len("method "):],
        # values are x fastest: reshape to (nz, ny, nx) and transpose so that field[i, j, k] is sample (i, j, k)
        "field": values.reshape(nz, ny, nx).transpose(2, 1, 0),
    }


def check(condition, what):
    if not condition:
        print(f"FAILED: {what}")
        sys.exit(1)


with tempfile.TemporaryDirectory() as folder:
    def bake(name, *extra):
        out = os.path.join(folder, name)
        subprocess.run([sdfgen, "bake", MESH, "--res", "12", "-o", out, *extra], check=True, stdout=subprocess.DEVNULL)
        return out

    ref = load_text(bake("f.sdf"))
    nx, ny, nz = ref["dims"]
    h = ref["voxel"]
    tolerance = 1e-6 * h  # the text format keeps the grid as the shortest decimal

    if mode == "numpy":
        a = np.load(bake("f.npy"))
        check(a.dtype == np.float32 and a.shape == (nx, ny, nz), f".npy dtype {a.dtype} shape {a.shape}")
        check(a.flags.f_contiguous, ".npy is Fortran-ordered (the field's buffer as is)")
        check(np.array_equal(a, ref["field"]), ".npy values equal the text file's, a[i, j, k] = sample (i, j, k)")

        z = np.load(bake("f.npz"))
        check(set(z.files) == {"sdf", "origin", "voxel_size", "dims", "method", "source"}, f".npz members {z.files}")
        check(np.array_equal(z["sdf"], ref["field"]), ".npz sdf equals the text file's values")
        check(z["origin"].dtype == np.float64 and np.allclose(z["origin"], ref["origin"], rtol=0, atol=tolerance), f"origin {z['origin']}")
        check(z["voxel_size"].shape == () and abs(float(z["voxel_size"]) - h) <= tolerance, f"voxel_size {z['voxel_size']}")
        check(tuple(z["dims"]) == (nx, ny, nz) and z["dims"].dtype == np.int64, f"dims {z['dims']}")
        check(str(z["method"]) == ref["method"], f"method '{z['method']}' vs '{ref['method']}'")
        check(str(z["source"]) == ref["source"], f"source '{z['source']}' vs '{ref['source']}'")
        # The documented one-liner for every sample's world position.
        positions = z["origin"] + (np.indices(z["sdf"].shape).transpose(1, 2, 3, 0) + 0.5) * z["voxel_size"]
        check(positions.shape == (nx, ny, nz, 3), "positions shape")
        i, j, k = 3, 5, 7
        check(np.allclose(positions[i, j, k], ref["origin"] + (np.array([i, j, k]) + 0.5) * h, rtol=0, atol=tolerance), "position of sample (3, 5, 7)")
        print(f"numpy reads .npy and .npz: {nx}x{ny}x{nz} samples equal the text file's")
    elif mode == "teem":
        nrrd = bake("f.nrrd")
        header = subprocess.run(["teem-unu", "head", nrrd], check=True, capture_output=True, text=True).stdout
        check(f"sizes: {nx} {ny} {nz}" in header, f"unu head: {header}")
        flat = subprocess.run(["teem-unu", "reshape", "-i", nrrd, "-s", str(nx * ny * nz)], check=True, capture_output=True).stdout
        text = subprocess.run(["teem-unu", "save", "-f", "text"], input=flat, check=True, capture_output=True).stdout.decode()
        values = np.array(text.split(), dtype=np.float32)  # x fastest, printed with 8 significant digits
        expected = ref["field"].transpose(2, 1, 0).ravel()
        check(values.shape == expected.shape and np.allclose(values, expected, rtol=1e-6, atol=1e-6 * h), "unu's values equal the text file's")
        print(f"teem's unu reads .nrrd: {nx}x{ny}x{nz} samples equal the text file's")
    else:
        grid = vdb.read(bake("f.vdb"), "surface")
        check(grid.gridClass == vdb.GridClass.LEVEL_SET, f"grid class {grid.gridClass}")
        check(grid.activeVoxelCount() == nx * ny * nz, f"dense: {grid.activeVoxelCount()} active voxels")
        check(grid["sdfgen_method"] == ref["method"], "sdfgen_method metadata")
        accessor = grid.getConstAccessor()
        for i in range(nx):
            for j in range(ny):
                for k in range(nz):
                    check(accessor.getValue((i, j, k)) == ref["field"][i, j, k], f"value at ({i}, {j}, {k})")
        world = grid.transform.indexToWorld((3, 5, 7))
        check(np.allclose(world, ref["origin"] + (np.array([3, 5, 7]) + 0.5) * h, rtol=0, atol=tolerance), f"index (3, 5, 7) at {world}")

        band = vdb.read(bake("band.vdb", "--band", "2"), "surface")
        check(abs(band.background - 2 * h) <= tolerance, f"band background {band.background}")
        near = int(np.count_nonzero(np.abs(ref["field"]) < np.float32(2 * h)))
        check(band.activeVoxelCount() == near, f"band: {band.activeVoxelCount()} active voxels, {near} within 2 voxels")
        print(f"pyopenvdb reads .vdb: {nx}x{ny}x{nz} samples equal the text file's; --band 2 keeps {near}")
