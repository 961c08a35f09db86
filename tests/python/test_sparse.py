"""sdfgen.SparseField: narrow-band bakes and sparse files, their bricks as numpy views without
copies, lookups and trilinear samples against the dense form, saving and loading."""
import gc
import os

import numpy as np
import pytest

import sdfgen

ROOT = os.environ.get("SDFGEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUNNY = os.path.join(ROOT, "assets", "bunny.obj")
TET_VERTICES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32)
RES = 64  # several bricks along each axis (the last cut at the grid's end), and whole bricks inside


@pytest.fixture(scope="module")
def bunny():
    return sdfgen.Mesh.load(BUNNY)


@pytest.fixture(scope="module")
def dense(bunny):
    return sdfgen.bake(bunny, res=RES)


def make_sparse(how, bunny, dense, folder):
    """The same band field two ways: baked with band=3, or loaded as sparse from the dense bake's file."""
    if how == "baked":
        return sdfgen.bake(bunny, res=RES, band=3)
    path = str(folder / "bunny.npz")
    dense.save(path)
    return sdfgen.SparseField.load(path)


@pytest.fixture(scope="module", params=["baked", "loaded"])
def sparse(request, bunny, dense, tmp_path_factory):
    return make_sparse(request.param, bunny, dense, tmp_path_factory.mktemp("sparse"))


def trilinear(values, origin, voxel, points):
    """The samples' trilinear interpolation at world points, clamped to the grid, in numpy."""
    dims = np.array(values.shape)
    g = np.clip((points - np.array(origin)) / voxel - 0.5, 0, dims - 1)
    lo = np.minimum(np.floor(g).astype(np.int64), np.maximum(dims - 2, 0))
    t = g - lo
    total = np.zeros(len(points))
    for corner in range(8):
        o = np.array([corner & 1, corner >> 1 & 1, corner >> 2 & 1])
        s = np.minimum(lo + o, dims - 1)
        w = np.prod(np.where(o == 1, t, 1.0 - t), axis=1)
        total += w * values[s[:, 0], s[:, 1], s[:, 2]].astype(np.float64)
    return total


def test_the_grid_and_band_are_the_dense_bakes(sparse, dense):
    assert isinstance(sparse, sdfgen.SparseField)
    assert sparse.dims == dense.dims and sparse.origin == dense.origin and sparse.voxel_size == dense.voxel_size
    assert sparse.band == 3
    assert sparse.background == np.float32(3 * dense.voxel_size)
    assert "SparseField" in repr(sparse) and "bricks" in repr(sparse)


@pytest.mark.parametrize("how", ["baked", "loaded"])
def test_bricks_are_views_without_copies_that_keep_the_field_alive(how, bunny, dense, tmp_path):
    field = make_sparse(how, bunny, dense, tmp_path)
    origins, values, boxes = field.brick_origins, field.brick_values, field.inside_boxes
    count = len(origins)
    assert origins.dtype == np.int32 and origins.shape == (count, 3) and count > 0 and np.all(origins % 8 == 0)
    assert values.dtype == np.float32 and values.shape == (8, 8, 8, count) and values.flags.f_contiguous
    assert boxes.dtype == np.int32 and boxes.shape == (len(boxes), 6) and len(boxes) > 0  # the bunny's inside
    for view in (origins, values, boxes):
        assert not view.flags.owndata and not view.flags.writeable
    for name, view in (("brick_origins", origins), ("brick_values", values), ("inside_boxes", boxes)):
        again = getattr(field, name)
        assert np.shares_memory(again, view) and again.__array_interface__["data"][0] == view.__array_interface__["data"][0], name
    with pytest.raises(ValueError):
        values[0, 0, 0, 0] = 0
    expected = (origins.copy(), values.copy(), boxes.copy())
    del field
    gc.collect()
    assert all(np.array_equal(a, b) for a, b in zip((origins, values, boxes), expected))


def test_to_dense_is_the_dense_bake_in_the_band_and_its_side_elsewhere(sparse, dense):
    d = sparse.to_dense()
    assert isinstance(d, sdfgen.Field) and d.dims == dense.dims and d.background == sparse.background
    values, exact, bg = d.values, dense.values, sparse.background
    band = np.abs(exact) < bg
    assert np.array_equal(values[band], exact[band])  # bit for bit
    assert np.all(np.abs(values[~band]) == bg)
    assert np.array_equal(np.signbit(values[~band]), np.signbit(exact[~band]))
    assert sparse.active_count == np.count_nonzero(band)
    assert 0 < sparse.active_count < values.size


def test_bricks_boxes_and_at_describe_the_dense_form(sparse):
    d = sparse.to_dense().values
    bg = sparse.background
    dims = np.array(sparse.dims)
    covered = np.zeros(d.shape, dtype=bool)
    values = sparse.brick_values
    for n, lo in enumerate(sparse.brick_origins):
        block = values[..., n]
        hi = np.minimum(lo + 8, dims)
        size = hi - lo
        assert np.array_equal(block[: size[0], : size[1], : size[2]], d[lo[0] : hi[0], lo[1] : hi[1], lo[2] : hi[2]])
        assert np.all(block[size[0] :] == bg) and np.all(block[:, size[1] :] == bg) and np.all(block[:, :, size[2] :] == bg)
        covered[lo[0] : hi[0], lo[1] : hi[1], lo[2] : hi[2]] = True
    inside = np.zeros(d.shape, dtype=bool)
    for lx, ly, lz, hx, hy, hz in sparse.inside_boxes:
        inside[lx:hx, ly:hy, lz:hz] = True
    assert not np.any(covered & inside)
    assert np.all(d[inside] == -bg) and np.all(d[~covered & ~inside] == bg)
    # The documented numpy lines for the sparse .npz (docs/field-format.md) rebuild it from these arrays.
    o, v, boxes = sparse.brick_origins, sparse.brick_values, sparse.inside_boxes
    nx, ny, nz = sparse.dims
    rebuilt = np.full(((nx + 7) // 8 * 8, (ny + 7) // 8 * 8, (nz + 7) // 8 * 8), bg, np.float32)
    for i0, j0, k0, i1, j1, k1 in boxes:
        rebuilt[i0:i1, j0:j1, k0:k1] = -bg
    a, b, c = np.indices((8, 8, 8))[..., None]
    rebuilt[o[:, 0] + a, o[:, 1] + b, o[:, 2] + c] = v
    assert np.array_equal(rebuilt[:nx, :ny, :nz], d)
    rng = np.random.default_rng(1)
    for i, j, k in zip(*(rng.integers(0, n, 300) for n in sparse.dims)):
        assert sparse.at(int(i), int(j), int(k)) == d[i, j, k]


def test_sample_is_trilinear_on_the_dense_form(sparse):
    d = sparse.to_dense()
    rng = np.random.default_rng(2)
    lo = np.array(d.origin)
    hi = lo + np.array(d.dims) * d.voxel_size
    points = rng.uniform(lo - d.voxel_size, hi + d.voxel_size, size=(2000, 3))  # some outside: clamped
    points[:8] = d.positions()[:2, :2, :2].reshape(-1, 3)  # at samples: the samples themselves
    got = sparse.sample(points)
    assert got.shape == (2000,) and got.dtype == np.float32
    assert np.array_equal(got[:8], d.values[:2, :2, :2].reshape(-1))
    assert np.allclose(got, trilinear(d.values, d.origin, d.voxel_size, points), rtol=0, atol=1e-6 * sparse.background)
    assert sparse.sample(points.reshape(40, 50, 3)).shape == (40, 50)
    assert np.array_equal(sparse.sample(points, threads=1), got)


def test_save_and_load_keep_it_sparse_or_make_it_dense(sparse, tmp_path):
    for extension in (".npz", ".vdb"):
        path = str(tmp_path / ("band" + extension))
        sparse.save(path)
        loaded = sdfgen.load_field(path)
        assert isinstance(loaded, sdfgen.SparseField), extension
        assert loaded.dims == sparse.dims and loaded.background == sparse.background
        assert np.array_equal(loaded.to_dense().values, sparse.to_dense().values)
    path = str(tmp_path / "band.npy")
    sparse.save(path)
    loaded = sdfgen.load_field(path)
    assert isinstance(loaded, sdfgen.Field)
    assert np.array_equal(loaded.values, sparse.to_dense().values)


def test_an_open_mesh_gets_the_dense_bakes_signs():
    mesh = sdfgen.Mesh(TET_VERTICES, TET_FACES[1:], name="open")
    dense = sdfgen.bake(mesh, res=24)
    sparse = sdfgen.bake(mesh, res=24, band=2)
    assert sparse.sign == dense.sign == "auto/winding"
    values, exact, bg = sparse.to_dense().values, dense.values, sparse.background
    band = np.abs(exact) < bg
    assert np.array_equal(values[band], exact[band])
    assert np.array_equal(np.signbit(values), np.signbit(exact))


def test_argument_errors_raise_sdfgen_error(sparse, bunny):
    for band in (-1.0, 0.5, float("nan"), float("inf")):
        with pytest.raises(ValueError, match=r"band must be 0 \(a dense field\) or a finite number of voxels from 1 to"):
            sdfgen.bake(bunny, res=8, band=band)
    nx, ny, nz = sparse.dims
    for ijk in ((nx, 0, 0), (0, -1, 0), (0, 0, nz)):
        with pytest.raises(sdfgen.Error, match=r"is outside the %dx%dx%d grid" % sparse.dims):
            sparse.at(*ijk)
    with pytest.raises(ValueError, match=r"\(P, 3\)"):
        sparse.sample(np.zeros((4, 2)))
    with pytest.raises(sdfgen.Error, match="threads must be"):
        sparse.sample(np.zeros((1, 3)), threads=-1)
    with pytest.raises(sdfgen.Error, match="band.xyz"):
        sparse.save("band.xyz")


def test_a_field_too_large_for_its_dense_form_stays_sparse(tmp_path):
    # A sparse .npz of 4096^3 samples (256 GiB dense) with one brick, written as documented.
    path = str(tmp_path / "huge.npz")
    background = np.float32(1.5)
    values = np.full((8, 8, 8, 1), background, np.float32)
    values[:, :, 4, 0] = np.array([-0.3, -0.2, -0.1, 0, 0.1, 0.2, 0.3, 0.4], np.float32)[:, None]  # a surface through the brick
    np.savez(path, brick_origins=np.array([[8, 16, 24]], np.int32), brick_values=np.asfortranarray(values),
             inside_boxes=np.zeros((0, 6), np.int32), background=background, dims=np.array([4096, 4096, 4096]),
             origin=np.zeros(3), voxel_size=np.float64(0.5), method=np.array("exact"), source=np.array("huge"))
    field = sdfgen.load_field(path)
    assert isinstance(field, sdfgen.SparseField) and field.dims == (4096, 4096, 4096)
    assert field.at(11, 20, 28) == np.float32(0.0) and field.at(0, 0, 0) == background
    assert field.active_count == 8 * 8  # |value| < 1.5: the plane k = 28 of the brick; the rest is +background
    assert field.sample(np.array([[11.5 * 0.5, 20.5 * 0.5, 28.5 * 0.5]]))[0] == np.float32(0.0)
    with pytest.raises(sdfgen.Error, match="keep it sparse"):
        field.to_dense()
    with pytest.raises(sdfgen.Error, match="huge.npy"):
        field.save(str(tmp_path / "huge.npy"))
    assert not os.path.exists(tmp_path / "huge.npy")
    field.save(str(tmp_path / "again.npz"))
    assert np.array_equal(sdfgen.load_field(str(tmp_path / "again.npz")).brick_values, field.brick_values)


def test_dims_whose_product_passes_2_to_the_64_are_refused(tmp_path):
    # Each axis below 2^31, their product exactly 2^64: refused on loading, never wrapped to 0 samples.
    path = str(tmp_path / "wrap.npz")
    np.savez(path, brick_origins=np.zeros((0, 3), np.int32), brick_values=np.zeros((8, 8, 8, 0), np.float32, order="F"),
             inside_boxes=np.zeros((0, 6), np.int32), background=np.float32(1.5), dims=np.array([4194304, 2097152, 2097152]),
             origin=np.zeros(3), voxel_size=np.float64(1e-6), method=np.array("exact"), source=np.array("wrap"))
    for load in (sdfgen.load_field, sdfgen.SparseField.load):
        with pytest.raises(sdfgen.Error, match=r"wrap.npz: grid 4194304x2097152x2097152 has more than 2\^58 samples"):
            load(path)


def test_sample_at_non_finite_points_raises_as_mesh_queries_do(sparse, bunny):
    for bad in (np.nan, np.inf, -np.inf):
        points = np.array([[0.0, 0, 0], [bad, 0, 0]])
        with pytest.raises(sdfgen.Error, match="query point 1 has a non-finite coordinate"):
            sparse.sample(points)
        with pytest.raises(sdfgen.Error, match="query point 1 has a non-finite coordinate"):
            bunny.signed_distance(points)


def test_overlapping_inside_boxes_are_refused(tmp_path):
    # Two boxes of one row of bricks, the second starting inside the first: at() and to_dense()
    # would disagree on the samples they share.
    path = str(tmp_path / "overlap.npz")
    np.savez(path, brick_origins=np.zeros((0, 3), np.int32), brick_values=np.zeros((8, 8, 8, 0), np.float32, order="F"),
             inside_boxes=np.array([[0, 0, 0, 32, 8, 8], [8, 0, 0, 16, 8, 8]], np.int32), background=np.float32(1.5),
             dims=np.array([32, 8, 8]), origin=np.zeros(3), voxel_size=np.float64(0.5), method=np.array("exact"),
             source=np.array("overlap"))
    for load in (sdfgen.load_field, sdfgen.SparseField.load):
        with pytest.raises(sdfgen.Error, match="overlap.npz: inside boxes 0 and 1 overlap"):
            load(path)


def test_another_programs_level_set_loads_sparse(tmp_path):
    # Two small spheres 10^6 voxels apart: the box of their active voxels is 10^6 x 29 x 29
    # samples (3.4 GB dense); read sparse, about a hundred bricks.
    vdb = pytest.importorskip("pyopenvdb")
    spheres = vdb.createLevelSetSphere(radius=10.0, center=(0, 0, 0), voxelSize=1.0, halfWidth=3.0)
    far = vdb.createLevelSetSphere(radius=10.0, center=(1e6, 0, 0), voxelSize=1.0, halfWidth=3.0)
    spheres.combine(far, lambda a, b: min(a, b))
    spheres.name = "spheres"
    path = str(tmp_path / "far.vdb")
    vdb.write(path, grids=[spheres])
    field = sdfgen.load_field(path)
    assert isinstance(field, sdfgen.SparseField)
    assert field.dims[0] > 1000000 and len(field.brick_origins) < 1000
    assert field.sample(np.array([[0.0, 0, 0], [1e6, 0, 0]])).max() < 0  # both centres inside
    assert field.sample(np.array([[5e5, 0, 0]]))[0] > 0
