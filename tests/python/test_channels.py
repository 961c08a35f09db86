"""A bake's and samples' channels in Python (gradient, closest point, nearest triangle): numpy views
of the field, equal to brute force in double on small meshes, the distances left as they were,
their .npz file, and the errors. Run with the other Python tests (ctest label python)."""
import numpy as np
import pytest

import sdfgen

ALL = "sdf,gradient,closest,triangle"


def box_mesh(half):
    corners = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], dtype=np.float64) * half
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return corners, np.array([tri for a, b, c, d in quads for tri in ((a, b, c), (a, c, d))], dtype=np.int64)


def closest_on_triangles(points, a, b, c):
    """Closest points (P, T, 3) of every point (P, 3) on every triangle (T, 3) and their squared distances, in double:
    the projection on the plane where it falls inside, else the nearest point of the three edges."""
    p = points[:, None, :]
    n = np.cross(b - a, c - a)
    projection = p - (((p - a) * n).sum(-1) / (n * n).sum(-1))[..., None] * n
    inside = np.ones(projection.shape[:2], dtype=bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= (np.cross(v - u, projection - u) * n).sum(-1) >= 0
    best = np.where(inside[..., None], projection, np.nan)
    best_squared = np.where(inside, ((p - projection) ** 2).sum(-1), np.inf)
    for u, v in ((a, b), (b, c), (c, a)):
        t = np.clip(((p - u) * (v - u)).sum(-1) / ((v - u) ** 2).sum(-1), 0, 1)
        q = u + t[..., None] * (v - u)
        squared = ((p - q) ** 2).sum(-1)
        nearer = squared < best_squared
        best = np.where(nearer[..., None], q, best)
        best_squared = np.where(nearer, squared, best_squared)
    return best, best_squared


def open_sheet():
    """A bent open sheet (auto signs it by the winding number)."""
    xs = np.linspace(-1, 1, 4)
    vertices = np.array([[x, y, 0.3 * x * x - 0.2 * y] for y in xs for x in xs])
    faces = []
    for j in range(3):
        for i in range(3):
            v = 4 * j + i
            faces += [(v, v + 1, v + 5), (v, v + 5, v + 4)]
    return vertices, np.array(faces, dtype=np.int64)


@pytest.mark.parametrize("shape", ["box", "sheet"])
def test_channels_equal_brute_force(shape):
    vertices, faces = box_mesh(np.array([1.0, 0.5, 0.75])) if shape == "box" else open_sheet()
    mesh = sdfgen.Mesh(vertices, faces)
    plain = sdfgen.bake(mesh, res=10)
    field = sdfgen.bake(mesh, res=10, channels=ALL)
    assert plain.gradient is None and plain.closest is None and plain.triangle is None
    assert np.array_equal(field.values.view(np.uint32), plain.values.view(np.uint32)), "the distances are untouched"
    nx, ny, nz = field.dims
    assert field.gradient.shape == (nx, ny, nz, 3) and field.gradient.dtype == np.float32
    assert field.closest.shape == (nx, ny, nz, 3) and field.closest.dtype == np.float32
    assert field.triangle.shape == (nx, ny, nz) and field.triangle.dtype == np.int32

    points = field.positions().reshape(-1, 3)
    # The mesh as sdfgen holds it (positions rounded to float), as the search measures it.
    closest, squared = closest_on_triangles(points, *(mesh.vertices[mesh.faces[:, c]] for c in range(3)))
    triangle = field.triangle.reshape(-1)
    rows = np.arange(len(points))
    nearest = np.sqrt(squared.min(axis=1))
    chosen = np.sqrt(squared[rows, triangle])
    assert np.all(chosen <= nearest * (1 + 1e-5) + 1e-7), "the triangle is the nearest or tied with it"
    c = closest[rows, triangle]
    assert np.allclose(field.closest.reshape(-1, 3), c, rtol=0, atol=1e-6)
    values = field.values.reshape(-1)
    assert np.all(values != 0)  # no sample on the surface, where the gradient would be the face normal
    expected = (points - c) / np.linalg.norm(points - c, axis=1)[:, None] * np.where(values < 0, -1.0, 1.0)[:, None]
    assert np.allclose(field.gradient.reshape(-1, 3), expected, rtol=0, atol=1e-6)


def test_channel_views_keep_the_field_alive_and_save_to_npz(tmp_path):
    vertices, faces = box_mesh(np.array([1.0, 1.0, 1.0]))
    field = sdfgen.bake(sdfgen.Mesh(vertices, faces), res=8, channels=["gradient", "triangle"])
    assert field.closest is None
    gradient, triangle = field.gradient, field.triangle
    expected_gradient, expected_triangle = gradient.copy(), triangle.copy()
    path = str(tmp_path / "f.npz")
    field.save(path)
    del field
    assert np.array_equal(gradient, expected_gradient) and np.array_equal(triangle, expected_triangle)
    saved = np.load(path)
    assert set(saved.files) >= {"sdf", "gradient", "triangle"} and "closest" not in saved.files
    assert np.array_equal(saved["gradient"], expected_gradient) and np.array_equal(saved["triangle"], expected_triangle)


def test_channel_errors(tmp_path):
    vertices, faces = box_mesh(np.array([1.0, 1.0, 1.0]))
    mesh = sdfgen.Mesh(vertices, faces)
    with pytest.raises(ValueError, match="unknown channel 'normals'"):
        sdfgen.bake(mesh, res=8, channels="sdf,normals")
    with pytest.raises(ValueError, match="come from the exact method's nearest triangles; method rays gives"):
        sdfgen.bake(mesh, res=8, method="rays", channels="gradient")
    field = sdfgen.bake(mesh, res=8, channels="gradient")
    for extension in ("npy", "sdf", "nrrd"):
        with pytest.raises(sdfgen.Error, match=r"holds the distance \(sdf\) only; for channels gradient write .npz or .vdb"):
            field.save(str(tmp_path / f"f.{extension}"))


def test_samples_with_channels():
    vertices, faces = open_sheet()
    mesh = sdfgen.Mesh(vertices, faces)
    points, sdf = sdfgen.sample(mesh, 500, seed=3)
    more = sdfgen.sample(mesh, 500, seed=3, channels=ALL)
    assert len(more) == 5
    points2, sdf2, gradient, closest, triangle = more
    assert np.array_equal(points, points2) and np.array_equal(sdf, sdf2)
    assert gradient.shape == (500, 3) and gradient.dtype == np.float32
    assert closest.shape == (500, 3) and triangle.shape == (500,) and triangle.dtype == np.int32
    only = sdfgen.sample(mesh, 500, seed=3, channels="triangle")
    assert len(only) == 3 and np.array_equal(only[2], triangle)
    p = points.astype(np.float64)
    _, squared = closest_on_triangles(p, *(mesh.vertices[mesh.faces[:, c]] for c in range(3)))
    assert np.all(np.sqrt(squared[np.arange(500), triangle]) <= np.sqrt(squared.min(axis=1)) * (1 + 1e-5) + 1e-7)
    away = p - closest
    expected = away / np.linalg.norm(away, axis=1)[:, None] * np.where(sdf < 0, -1.0, 1.0)[:, None]
    far = np.abs(sdf) > 1e-3  # where the float closest point gives the direction to 1e-4
    assert np.allclose(gradient[far], expected[far], atol=1e-4)


@pytest.mark.parametrize("name", sdfgen.CHANNELS)
def test_every_registered_channel_is_a_view_a_sample_array_and_an_npz_member(name, tmp_path):
    vertices, faces = box_mesh(np.array([1.0, 0.5, 0.75]))
    mesh = sdfgen.Mesh(vertices, faces)
    field = sdfgen.bake(mesh, res=8, channels=["sdf", name])
    view = getattr(field, name)
    assert view is not None and view.shape[:3] == tuple(field.dims) and view.dtype in (np.float32, np.int32)
    for other in sdfgen.CHANNELS:
        assert other == name or getattr(field, other) is None
    path = str(tmp_path / "f.npz")
    field.save(path)
    assert np.array_equal(np.load(path)[name], view)
    points, sdf, values = sdfgen.sample(mesh, 200, seed=1, channels=name)
    assert values.shape[0] == 200 and values.shape[1:] == view.shape[3:] and values.dtype == view.dtype
