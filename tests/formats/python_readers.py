#!/usr/bin/python3
"""Fields written by `sdfgen bake` read by the programs users read them with: numpy (.npy, .npz),
pyopenvdb (.vdb) or teem's unu (.nrrd), compared with the sdfgen-text file of the same bake.

Usage: python_readers.py numpy|band|openvdb|teem SDFGEN_BINARY SOURCE_DIR
band: a band field's sparse .npz read by the lines docs/field-format.md gives (numpy).
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

        # Channels: the same distances, and arrays that agree with them and with the mesh.
        c = np.load(bake("channels.npz", "--channels", "sdf,gradient,closest,triangle"))
        check(set(c.files) == set(z.files) | {"gradient", "closest", "triangle"}, f"channel members {c.files}")
        check(np.array_equal(c["sdf"], ref["field"]), "the sdf with channels equals the text file's values")
        gradient, closest, triangle = c["gradient"], c["closest"], c["triangle"]
        check(gradient.dtype == np.float32 and gradient.shape == (nx, ny, nz, 3), f"gradient {gradient.dtype} {gradient.shape}")
        check(closest.dtype == np.float32 and closest.shape == (nx, ny, nz, 3), f"closest {closest.dtype} {closest.shape}")
        check(triangle.dtype == np.int32 and triangle.shape == (nx, ny, nz), f"triangle {triangle.dtype} {triangle.shape}")
        away = positions - closest
        distance = np.linalg.norm(away, axis=-1)
        check(np.allclose(distance, np.abs(c["sdf"]), rtol=1e-5, atol=1e-5 * h), "|position - closest| is the distance")
        expected = away / distance[..., None] * np.sign(c["sdf"])[..., None]
        far = distance > 0.1 * h  # where the float closest point still gives the direction to 1e-5
        check(np.allclose(gradient[far], expected[far], atol=1e-5), "gradient = sign * (position - closest) / distance")
        check(np.allclose(np.linalg.norm(gradient, axis=-1), 1, atol=1e-6), "gradient is a unit vector")
        vertices, faces = [], []
        with open(MESH) as f:
            for line in f:
                if line.startswith("v "):
                    vertices.append([float(x) for x in line.split()[1:4]])
                elif line.startswith("f "):
                    faces.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
        vertices, faces = np.array(vertices), np.array(faces)
        check(triangle.min() >= 0 and triangle.max() < len(faces), "triangle indices index the mesh's faces")
        # The closest point lies on its triangle: barycentric weights >= 0 that rebuild it.
        a, b, t = (vertices[faces[triangle, corner]] for corner in range(3))
        e1, e2, q = b - a, t - a, closest - a
        d11, d12, d22 = (e1 * e1).sum(-1), (e1 * e2).sum(-1), (e2 * e2).sum(-1)
        q1, q2 = (q * e1).sum(-1), (q * e2).sum(-1)
        det = d11 * d22 - d12 * d12
        u, v = (d22 * q1 - d12 * q2) / det, (d11 * q2 - d12 * q1) / det
        rebuilt = a + u[..., None] * e1 + v[..., None] * e2
        check(np.abs(rebuilt - closest).max() < 1e-5 and min(u.min(), v.min(), (1 - u - v).min()) > -1e-4, "closest lies on its triangle")

        s = os.path.join(folder, "samples.npz")
        subprocess.run([sdfgen, "sample", MESH, "-n", "500", "-o", s, "--channels", "gradient,closest,triangle"], check=True,
                       stdout=subprocess.DEVNULL)
        samples = np.load(s)
        check(set(samples.files) == {"points", "sdf", "gradient", "closest", "triangle"}, f"sample members {samples.files}")
        check(samples["gradient"].shape == (500, 3) and samples["gradient"].dtype == np.float32, "samples' gradient (n, 3) float32")
        check(samples["triangle"].shape == (500,) and samples["triangle"].dtype == np.int32, "samples' triangle (n,) int32")
        check(np.allclose(np.linalg.norm(samples["points"] - samples["closest"], axis=-1), np.abs(samples["sdf"]), rtol=1e-4, atol=1e-5),
              "samples' |point - closest| is the distance")
        print("numpy reads the channels of .npz fields and samples: they agree with the distances and the mesh")
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
    elif mode == "band":
        res = ["--res", "64"]
        band_npz = os.path.join(folder, "bunny-band.npz")
        subprocess.run([sdfgen, "bake", MESH, *res, "--band", "3", "-o", band_npz], check=True, stdout=subprocess.DEVNULL)
        # A band field's sparse .npz, rebuilt and looked up by the very lines docs/field-format.md
        # gives, equals the dense bake in the band and has its sign everywhere else.
        with open(os.path.join(root, "docs", "field-format.md")) as f:
            doc = f.read()
        marker = "<!-- sparse-npz-snippet"
        check(marker in doc, "the documented sparse .npz snippet")
        snippet = doc[doc.index("```python\n", doc.index(marker)) + len("```python\n"):]
        snippet = snippet[:snippet.index("```")]
        dense_npy = os.path.join(folder, "bunny-dense.npy")
        subprocess.run([sdfgen, "bake", MESH, *res, "-o", dense_npy], check=True, stdout=subprocess.DEVNULL)
        reference = np.load(dense_npy)
        space = {"np": np}
        cwd = os.getcwd()
        os.chdir(folder)
        try:
            exec(snippet, space)
        finally:
            os.chdir(cwd)
        dense, bg, o = space["dense"], float(space["bg"]), space["o"]
        check(dense.shape == reference.shape, f"rebuilt shape {dense.shape} vs {reference.shape}")
        check(abs(bg - 3 * float(np.load(band_npz)["voxel_size"])) < 1e-6 * bg, f"background {bg} is 3 voxels")
        in_band = np.abs(reference) < np.float32(bg)
        check(in_band.any() and not in_band.all(), "the band holds some samples and not all")
        check(np.array_equal(dense[in_band], reference[in_band]), "in the band: the dense bake's values, bit for bit")
        check(np.array_equal(np.sign(dense[~in_band]), np.sign(reference[~in_band])) and np.all(np.abs(dense[~in_band]) == np.float32(bg)),
              "outside the band: +-background with the dense bake's sign")
        nx, ny, nz = reference.shape
        check(len(o) < ((nx + 7) // 8) * ((ny + 7) // 8) * ((nz + 7) // 8) and len(space["boxes"]) > 0,
              f"{len(o)} bricks and {len(space['boxes'])} inside boxes: sparse")
        for i, j, k in [(0, 0, 0), (nx // 2, ny // 2, nz // 2), (nx - 1, ny - 1, nz - 1), (nx // 3, ny // 2, nz // 4)]:
            check(space["sample"](i, j, k) == dense[i, j, k], f"sample({i}, {j}, {k}) equals the rebuilt array")
        for i, j, k in np.argwhere(in_band)[::97]:
            check(space["sample"](i, j, k) == reference[i, j, k], f"sample({i}, {j}, {k}) in the band")
        print(f"numpy reads a band field's .npz as documented: {len(o)} bricks, equal to the dense bake in the band and by sign outside")
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

        # A band field's level set: the dense bake's values in the band, +-background with its sign
        # outside, the inside as inactive -background tiles.
        fine = ["--res", "64"]
        band_path, dense_npy = os.path.join(folder, "fine-band.vdb"), os.path.join(folder, "fine.npy")
        subprocess.run([sdfgen, "bake", MESH, *fine, "--band", "3", "-o", band_path], check=True, stdout=subprocess.DEVNULL)
        subprocess.run([sdfgen, "bake", MESH, *fine, "-o", dense_npy], check=True, stdout=subprocess.DEVNULL)
        reference = np.load(dense_npy)
        level_set = vdb.read(band_path, "surface")
        bg = level_set.background
        check(level_set.gridClass == vdb.GridClass.LEVEL_SET and bg > 0, f"band level set: class {level_set.gridClass}, background {bg}")
        in_band = np.abs(reference) < np.float32(bg)
        check(level_set.activeVoxelCount() == int(np.count_nonzero(in_band)), f"band: {level_set.activeVoxelCount()} active voxels")
        values = np.zeros(reference.shape, dtype=np.float32)
        level_set.copyToArray(values)
        check(np.array_equal(values[in_band], reference[in_band]), "band: the dense bake's values in the band")
        check(np.array_equal(values[~in_band], np.where(reference[~in_band] < 0, -bg, bg).astype(np.float32)),
              "band: +-background with the dense bake's sign outside it")
        tiles = [t for t in level_set.iterOffValues() if t["depth"] < 3 and t["value"] == -bg]
        check(len(tiles) > 0, "band: the inside is inactive -background tiles")
        print(f"pyopenvdb reads a band level set: {level_set.activeVoxelCount()} active voxels, {len(tiles)} inside tiles")

        # Channels: grids of their names beside "surface", at the same voxels, holding the .npz's arrays.
        channels = np.load(bake("channels.npz", "--channels", "gradient,closest,triangle"))
        for band in ("0", "2"):
            path = bake(f"channels{band}.vdb", "--channels", "gradient,closest,triangle", "--band", band)
            # (Debian's pyopenvdb reads float, bool and Vec3S grids only, not the Int32Grid "triangle".)
            surface = vdb.read(path, "surface")
            for name in ("gradient", "closest"):
                grid = vdb.read(path, name)
                check(isinstance(grid, vdb.Vec3SGrid), f"{name} is a Vec3SGrid")
                check(grid.activeVoxelCount() == surface.activeVoxelCount(), f"{name}: the surface grid's active voxels")
                accessor, active = grid.getConstAccessor(), surface.getConstAccessor()
                for i in range(nx):
                    for j in range(ny):
                        for k in range(nz):
                            if active.isValueOn((i, j, k)):
                                check(np.array_equal(np.array(accessor.getValue((i, j, k)), dtype=np.float32), channels[name][i, j, k]),
                                      f"{name} at ({i}, {j}, {k})")
        print("pyopenvdb reads the gradient and closest grids of .vdb fields: they equal the .npz's arrays")
