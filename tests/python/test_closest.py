"""Mesh.closest and sdfgen.torch.closest, the closest-hit record (triangle, point, barycentrics,
distance, sign, gradient), against brute force in double; the gradient at distance 0 (the face
normal) the same in numpy and torch (as Model::query's: tests/test_query.cpp), with finite
gradients to points and vertices there. Run by ctest (label python) with PYTHONPATH=build/python
and SDFGEN_SOURCE_DIR set."""
import os

import numpy as np
import pytest

import sdfgen

ROOT = os.environ.get("SDFGEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUNNY = os.path.join(ROOT, "assets", "bunny.obj")

# An octahedron (closed) whose vertices are slightly displaced: no symmetric ties.
OCTA_VERTICES = np.array([[1, 0.02, 0], [-0.97, 0, 0.03], [0.01, 1.05, 0], [0, -1, 0.02], [0.03, 0, 0.95], [0, 0.04, -1.02]])
OCTA_FACES = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])


def brute_hits(points, vertices, faces):
    """Per point, in double over every triangle (Ericson's closest points): the nearest triangle, the
    distance to it and the gap to the second nearest."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    distances = np.empty((len(points), len(faces)))
    for t in range(len(faces)):
        distances[:, t] = np.linalg.norm(points - closest_on_triangle(points, a[t], b[t], c[t]), axis=-1)
    order = np.argsort(distances, axis=1, kind="stable")
    rows = np.arange(len(points))
    return order[:, 0], distances[rows, order[:, 0]], distances[rows, order[:, 1]] - distances[rows, order[:, 0]]


def closest_on_triangle(p, a, b, c):
    """Ericson's closest point on one triangle (a, b, c) for each of the points p (P, 3), in double."""
    ab, ac, ap, bp, cp = b - a, c - a, p - a, p - b, p - c
    d1, d2, d3, d4, d5, d6 = ap @ ab, ap @ ac, bp @ ab, bp @ ac, cp @ ab, cp @ ac
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        result = a + np.outer(vb / (va + vb + vc), ab) + np.outer(vc / (va + vb + vc), ac)
        cases = [
            ((d4 - d3 >= 0) & (d5 - d6 >= 0) & (va <= 0), b + np.outer((d4 - d3) / ((d4 - d3) + (d5 - d6)), c - b)),
            ((d2 >= 0) & (d6 <= 0) & (vb <= 0), a + np.outer(d2 / (d2 - d6), ac)),
            ((d6 >= 0) & (d5 <= d6), np.broadcast_to(c, p.shape)),
            ((d1 >= 0) & (d3 <= 0) & (vc <= 0), a + np.outer(d1 / (d1 - d3), ab)),
            ((d3 >= 0) & (d4 <= d3), np.broadcast_to(b, p.shape)),
            ((d1 <= 0) & (d2 <= 0), np.broadcast_to(a, p.shape)),
        ]
    for mask, value in cases:  # the last that applies wins, in Ericson's order of tests
        result = np.where(mask[:, None], value, result)
    return result


@pytest.fixture(scope="module")
def bunny():
    return sdfgen.Mesh.load(BUNNY)


def random_points(mesh, count, seed):
    lo, hi = (np.array(b) for b in mesh.bounds)
    return np.random.default_rng(seed).uniform(lo - 0.2 * (hi - lo), hi + 0.2 * (hi - lo), size=(count, 3))


@pytest.mark.parametrize("name", ["octahedron", "bunny"])
def test_the_record_equals_brute_force_in_double(name, bunny):
    mesh = bunny if name == "bunny" else sdfgen.Mesh(OCTA_VERTICES, OCTA_FACES)
    vertices, faces = mesh.vertices, mesh.faces
    points = random_points(mesh, 300, seed=5)
    hit = mesh.closest(points)
    assert isinstance(hit, sdfgen.ClosestHit)
    assert hit.triangle.dtype == np.int64 and hit.triangle.shape == (300,)
    assert hit.point.dtype == np.float64 and hit.point.shape == (300, 3)
    assert hit.barycentric.dtype == np.float64 and hit.barycentric.shape == (300, 3)
    assert hit.distance.dtype == np.float32 and hit.sign.dtype == np.int8 and hit.gradient.shape == (300, 3)
    triangle, distance, gap = brute_hits(points, vertices, faces)
    # Where one triangle is nearest, it is the one; where several tie (at a shared edge or vertex),
    # the point found is at the nearest distance and on the triangle named (its barycentrics below).
    unique = gap > 1e-6
    assert unique.sum() > len(points) / 5
    assert np.array_equal(hit.triangle[unique], triangle[unique])
    mine = np.linalg.norm(points - hit.point, axis=-1)
    assert np.allclose(mine, distance, rtol=0, atol=1e-6)
    # The barycentrics rebuild the point from the triangle's corners, sum to 1 and are never negative.
    corners = vertices[faces[hit.triangle]]
    assert np.allclose(np.einsum("pk,pkx->px", hit.barycentric, corners), hit.point, rtol=0, atol=1e-12)
    assert np.allclose(hit.barycentric.sum(axis=1), 1, rtol=0, atol=1e-12) and hit.barycentric.min() >= -1e-12
    # Distance, sign and gradient are those of the other queries.
    assert np.array_equal(hit.distance, mesh.signed_distance(points))
    assert np.array_equal(hit.sign, np.where(np.signbit(hit.distance), -1, 1))
    assert np.array_equal(hit.triangle, mesh.nearest_triangle(points))
    assert np.array_equal(hit.point, mesh.closest_points(points))
    expected = (points - hit.point) / mine[:, None] * hit.sign[:, None]
    assert np.allclose(hit.gradient, expected, rtol=0, atol=1e-6)
    # Any shape (..., 3).
    assert mesh.closest(points.reshape(3, 100, 3)).barycentric.shape == (3, 100, 3)


def test_the_gradient_at_distance_zero_is_the_face_normal_in_every_front_end():
    torch = pytest.importorskip("torch", reason="torch is not installed (Debian: apt-get install python3-torch)")
    import sdfgen.torch as st

    # A tetrahedron with one face in z = 0 whose outward normal is -z: points on it are at distance 0
    # in double and in the mesh's float copy.
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    mesh = sdfgen.Mesh(vertices, faces)
    on_base = np.array([[0.25, 0.25, 0.0], [0.5, 0.125, 0.0], [0.125, 0.0625, 0.0]])
    normal = np.array([0.0, 0.0, -1.0])
    hit = mesh.closest(on_base)
    assert np.all(hit.distance == 0) and np.all(hit.triangle == 0)
    assert np.array_equal(hit.gradient, np.tile(normal, (3, 1)))
    assert np.allclose(hit.barycentric, [[0.5, 0.25, 0.25], [0.375, 0.125, 0.5], [0.8125, 0.0625, 0.125]], rtol=0, atol=1e-15)
    # sdfgen.torch: a Mesh, and vertices and faces (vertices get -w * n), and the record.
    v, f = torch.from_numpy(vertices).requires_grad_(), torch.from_numpy(faces)
    for form in ([mesh], [v, f]):
        points = torch.from_numpy(on_base).requires_grad_()
        distance = st.signed_distance(points, *form)
        assert torch.equal(distance.detach(), torch.zeros(3, dtype=torch.float64))
        distance.sum().backward()
        assert torch.equal(points.grad, torch.from_numpy(np.tile(normal, (3, 1))))
        unsigned_points = points.detach().clone().requires_grad_()
        st.unsigned_distance(unsigned_points, *(x.detach() if isinstance(x, torch.Tensor) else x for x in form)).sum().backward()
        assert torch.equal(unsigned_points.grad, points.grad)  # the normal as the triangle winds
        record = st.closest(points.detach(), *form)
        assert torch.equal(record.gradient, points.grad) and torch.equal(record.triangle, torch.zeros(3, dtype=torch.int64))
    expected_vertices = -np.einsum("pk,x->kx", hit.barycentric, normal)  # corners 0, 2, 1 of face [0, 2, 1]
    assert torch.allclose(v.grad[[0, 2, 1]], torch.from_numpy(expected_vertices), rtol=0, atol=1e-15)
    assert torch.isfinite(v.grad).all() and torch.equal(v.grad[3], torch.zeros(3, dtype=torch.float64))


def test_torch_record_equals_numpy_and_carries_gradients(bunny):
    torch = pytest.importorskip("torch", reason="torch is not installed (Debian: apt-get install python3-torch)")
    import sdfgen.torch as st

    points = random_points(bunny, 500, seed=9)
    hit = bunny.closest(points)
    p = torch.from_numpy(points).requires_grad_()
    record = st.closest(p, bunny)
    assert isinstance(record, sdfgen.ClosestHit)
    assert torch.equal(record.triangle, torch.from_numpy(hit.triangle))
    assert torch.equal(record.distance.detach().float(), torch.from_numpy(hit.distance))  # measured in double, rounded as Mesh's
    assert torch.equal(record.sign, torch.from_numpy(hit.sign))
    assert torch.allclose(record.point.detach(), torch.from_numpy(hit.point), rtol=0, atol=1e-12)
    assert torch.allclose(record.barycentric, torch.from_numpy(hit.barycentric), rtol=0, atol=1e-9)
    assert torch.allclose(record.gradient, torch.from_numpy(hit.gradient), rtol=0, atol=1e-6)
    assert record.point.requires_grad and record.distance.requires_grad and not record.barycentric.requires_grad
    record.distance.sum().backward()
    assert torch.equal(p.grad, record.gradient)
    # From tensors: measured in double from the given vertices, differentiable with respect to them.
    vertices = torch.tensor(bunny.vertices, requires_grad=True)
    faces = torch.from_numpy(bunny.faces)
    tensors = st.closest(p.detach(), vertices, faces)
    assert torch.equal(tensors.triangle, record.triangle)
    corners = vertices.detach()[faces[tensors.triangle]]
    assert torch.allclose(torch.einsum("pk,pkx->px", tensors.barycentric, corners), tensors.point.detach(), rtol=0, atol=1e-12)
    (tensors.distance.sum() + tensors.point.sum()).backward()
    assert torch.isfinite(vertices.grad).all() and vertices.grad.abs().sum() > 0
