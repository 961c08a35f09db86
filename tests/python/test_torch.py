"""sdfgen.torch: values equal to the numpy queries and to brute force in double, gradients against
finite differences (gradcheck at eps 1e-7) for points and vertices on closed and open meshes,
dtype/shape/device round trips, errors. Skipped when torch is missing (Debian: python3-torch).
Run by ctest (label python) with PYTHONPATH=build/python and SDFGEN_SOURCE_DIR set."""
import os
import subprocess
import sys

import numpy as np
import pytest

import sdfgen

torch = pytest.importorskip("torch", reason="torch is not installed (Debian: apt-get install python3-torch)")
import sdfgen.torch as st  # noqa: E402

ROOT = os.environ.get("SDFGEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUNNY = os.path.join(ROOT, "assets", "bunny.obj")

# A tetrahedron with a vertex off the axes (no symmetric ties), closed and without its base (open).
TET_VERTICES = np.array([[0.1, -0.05, 0.02], [1.1, 0.1, -0.1], [-0.05, 0.9, 0.12], [0.2, 0.15, 1.05]])
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
# An octahedron (closed, eight triangles) whose vertices are slightly displaced.
OCTA_VERTICES = np.array([[1, 0.02, 0], [-0.97, 0, 0.03], [0.01, 1.05, 0], [0, -1, 0.02], [0.03, 0, 0.95], [0, 0.04, -1.02]])
OCTA_FACES = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
MESHES = {"closed": (OCTA_VERTICES, OCTA_FACES), "closed-tetrahedron": (TET_VERTICES, TET_FACES), "open": (TET_VERTICES, TET_FACES[1:])}


def brute_closest(points, vertices, faces):
    """(P, T, 3) closest points of every point on every triangle, in double (Ericson's regions)."""
    p = points[:, None, :]
    a, b, c = (vertices[faces[:, k]][None] for k in range(3))
    ab, ac, ap, bp, cp = b - a, c - a, p - a, p - b, p - c
    dot = lambda x, y: np.sum(x * y, axis=-1)  # noqa: E731
    d1, d2, d3, d4, d5, d6 = dot(ab, ap), dot(ac, ap), dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denominator = 1.0 / (va + vb + vc)
        result = a + ab * (vb * denominator)[..., None] + ac * (vc * denominator)[..., None]
        cases = [
            ((d4 - d3 >= 0) & (d5 - d6 >= 0) & (va <= 0), b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))[..., None]),
            ((d2 >= 0) & (d6 <= 0) & (vb <= 0), a + ac * (d2 / (d2 - d6))[..., None]),
            ((d6 >= 0) & (d5 <= d6), np.broadcast_to(c, result.shape)),
            ((d1 >= 0) & (d3 <= 0) & (vc <= 0), a + ab * (d1 / (d1 - d3))[..., None]),
            ((d3 >= 0) & (d4 <= d3), np.broadcast_to(b, result.shape)),
            ((d1 <= 0) & (d2 <= 0), np.broadcast_to(a, result.shape)),
        ]
    for mask, value in cases:  # the last that applies wins, in Ericson's order of tests
        result = np.where(mask[..., None], value, result)
    return result


def brute_nearest(points, vertices, faces):
    """Distances and closest points in double, and whether each point is clear of the medial axis:
    every triangle that comes within 1e-3 of the nearest distance has the same closest point."""
    closest = brute_closest(points, vertices, faces)
    distances = np.linalg.norm(points[:, None, :] - closest, axis=-1)
    best = np.argmin(distances, axis=1)
    rows = np.arange(len(points))
    nearest = closest[rows, best]
    near = distances <= distances[rows, best][:, None] + 1e-3
    same = np.linalg.norm(closest - nearest[:, None, :], axis=-1) < 1e-9
    clear = np.all(~near | same, axis=1)
    return distances[rows, best], nearest, clear


def clear_points(vertices, faces, count, seed, band=1e-3):
    """Random points near the mesh, at least `band` from the surface and clear of the medial axis."""
    rng = np.random.default_rng(seed)
    lo, hi = vertices.min(axis=0) - 0.3, vertices.max(axis=0) + 0.3
    points = rng.uniform(lo, hi, size=(8 * count, 3))
    distance, _, clear = brute_nearest(points, vertices, faces)
    points = points[clear & (distance > band)]
    assert len(points) >= count
    return points[:count]


@pytest.fixture(scope="module")
def bunny():
    return sdfgen.Mesh.load(BUNNY)


def test_importing_sdfgen_does_not_import_torch():
    script = "import sys, sdfgen; assert 'torch' not in sys.modules; import sdfgen.torch; assert 'torch' in sys.modules"
    subprocess.run([sys.executable, "-c", script], check=True, timeout=120, env=os.environ)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_mesh_form_equals_the_numpy_queries(bunny, dtype):
    lo, hi = (np.array(b) for b in bunny.bounds)
    points = np.random.default_rng(3).uniform(lo - 0.1, hi + 0.1, size=(5000, 3)).astype(dtype)
    tensor = torch.from_numpy(points)
    signed = st.signed_distance(tensor, bunny)
    unsigned = st.unsigned_distance(tensor, bunny)
    closest = st.closest_points(tensor, bunny)
    assert signed.dtype == unsigned.dtype == closest.dtype == tensor.dtype
    assert signed.shape == unsigned.shape == (5000,) and closest.shape == (5000, 3)
    # Measured in double: rounded to float32 it is numpy's value exactly.
    assert np.array_equal(signed.numpy().astype(np.float32), bunny.signed_distance(points))
    assert np.array_equal(unsigned.numpy().astype(np.float32), bunny.unsigned_distance(points))
    assert np.array_equal(st.signed_distance(tensor, bunny, sign="winding").numpy().astype(np.float32),
                          bunny.signed_distance(points, sign="winding"))
    expected = bunny.closest_points(points)
    if dtype == np.float64:
        assert np.array_equal(closest.numpy(), expected)
        assert np.array_equal(np.abs(signed.numpy()), unsigned.numpy())
    else:
        assert np.array_equal(closest.numpy(), expected.astype(np.float32))


@pytest.mark.parametrize("name", MESHES)
def test_tensor_form_is_measured_in_double_from_the_given_vertices(name):
    vertices, faces = MESHES[name]
    points = np.random.default_rng(4).uniform(-1.3, 1.3, size=(3000, 3))
    distance, closest, _ = brute_nearest(points, vertices, faces)
    v, f, p = torch.from_numpy(vertices), torch.from_numpy(faces), torch.from_numpy(points)
    signed = st.signed_distance(p, v, f).numpy()
    assert np.max(np.abs(np.abs(signed) - distance)) < 1e-14
    assert np.max(np.abs(st.unsigned_distance(p, v, f).numpy() - distance)) < 1e-14
    assert np.max(np.abs(st.closest_points(p, v, f).numpy() - closest)) < 1e-14
    reference = sdfgen.Mesh(vertices, faces).signed_distance(points)  # signs from the same rule
    assert np.array_equal(np.signbit(signed), np.signbit(reference))
    assert np.max(np.abs(signed - reference)) < 1e-6  # numpy's float32 values
    if name == "open":  # the winding number signs the open mesh: points far below it are outside
        assert st.signed_distance(torch.tensor([[0.3, 0.3, -2.0]], dtype=torch.float64), v, f).item() > 0


@pytest.mark.parametrize("name", MESHES)
@pytest.mark.parametrize("function", ["signed_distance", "unsigned_distance", "closest_points"])
def test_gradcheck_points_and_vertices(name, function):
    vertices, faces = MESHES[name]
    points = torch.tensor(clear_points(vertices, faces, 24, seed=5), requires_grad=True)
    v = torch.tensor(vertices, requires_grad=True)
    f = torch.from_numpy(faces)
    call = getattr(st, function)
    assert torch.autograd.gradcheck(lambda p, v: call(p, v, f), (points, v), eps=1e-7, atol=1e-6, rtol=1e-5)
    mesh = sdfgen.Mesh(vertices, faces)
    assert torch.autograd.gradcheck(lambda p: call(p, mesh), (points,), eps=1e-7, atol=1e-6, rtol=1e-5)


def test_gradcheck_on_the_bunny_points(bunny):
    vertices, faces = bunny.vertices, bunny.faces
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    points = np.random.default_rng(6).uniform(lo - 0.05, hi + 0.05, size=(400, 3))
    _, _, clear = brute_nearest(points, vertices, faces)
    points = torch.tensor(points[clear][:40], requires_grad=True)
    assert len(points) == 40
    assert torch.autograd.gradcheck(lambda p: st.signed_distance(p, bunny), (points,), eps=1e-7, atol=1e-6, rtol=1e-5)


def test_zero_area_triangles_are_dropped_and_indices_kept():
    vertices, faces = MESHES["closed"]
    with_slivers = np.concatenate([[[0, 0, 1], [2, 2, 5]], faces])  # zero area: dropped, the others shift
    points = torch.tensor(clear_points(vertices, faces, 24, seed=11), requires_grad=True)
    v = torch.tensor(vertices, requires_grad=True)
    for function in (st.signed_distance, st.closest_points):
        plain = function(points, v, torch.from_numpy(faces))
        with pytest.warns(sdfgen.Warning, match="<tensors>: dropped 2 zero-area triangles"):
            slivers = function(points, v, torch.from_numpy(with_slivers))
            assert torch.autograd.gradcheck(lambda p, v: function(p, v, torch.from_numpy(with_slivers)), (points, v),
                                            eps=1e-7, atol=1e-6, rtol=1e-5)
        assert torch.equal(plain, slivers)


def test_gradients_point_from_the_closest_point():
    vertices, faces = MESHES["closed"]
    points = torch.tensor(clear_points(vertices, faces, 200, seed=7), requires_grad=True)
    v = torch.tensor(vertices, requires_grad=True)
    f = torch.from_numpy(faces)
    signed = st.signed_distance(points, v, f)
    signed.sum().backward()
    closest = st.closest_points(points.detach(), v.detach(), f)
    direction = points.detach() - closest
    expected = direction / torch.linalg.norm(direction, dim=-1, keepdim=True) * torch.sign(signed.detach())[:, None]
    assert torch.allclose(points.grad, expected, rtol=0, atol=1e-12)
    assert torch.all(torch.abs(torch.linalg.norm(points.grad, dim=-1) - 1) < 1e-12)
    # Moving the whole mesh moves every distance the other way: the weights sum to one.
    assert torch.allclose(v.grad.sum(dim=0), -points.grad.sum(dim=0), rtol=0, atol=1e-10)
    inside = signed.detach() < 0
    assert inside.any() and (~inside).any()
    unsigned_points = points.detach().clone().requires_grad_(True)
    st.unsigned_distance(unsigned_points, v.detach(), f).sum().backward()
    assert torch.allclose(unsigned_points.grad, points.grad * torch.sign(signed.detach())[:, None], rtol=0, atol=1e-15)


def test_the_face_normal_on_the_surface():
    # The base (face [0, 2, 1] in z = 0) faces -z; more in test_closest.py.
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    v, f = torch.from_numpy(vertices), torch.from_numpy(TET_FACES)
    for mesh in ([sdfgen.Mesh(vertices, TET_FACES)], [v, f]):
        on_base = torch.tensor([0.25, 0.25, 0.0], dtype=torch.float64, requires_grad=True)
        distance = st.signed_distance(on_base, *mesh)
        assert distance.shape == () and distance.item() == 0
        distance.backward()
        assert torch.equal(on_base.grad, torch.tensor([0.0, 0.0, -1.0], dtype=torch.float64))


@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_dtypes_and_shapes_round_trip(dtype):
    vertices, faces = MESHES["closed"]
    v = torch.tensor(vertices, dtype=dtype, requires_grad=True)
    f = torch.tensor(faces, dtype=torch.int32)
    points = torch.tensor(clear_points(vertices, faces, 24, seed=8).reshape(2, 4, 3, 3), dtype=dtype, requires_grad=True)
    signed = st.signed_distance(points, v, f)
    closest = st.closest_points(points, v, f)
    assert signed.shape == (2, 4, 3) and signed.dtype == dtype
    assert closest.shape == (2, 4, 3, 3) and closest.dtype == dtype
    (signed.sum() + closest.sum()).backward()
    assert points.grad.shape == points.shape and points.grad.dtype == dtype
    assert v.grad.shape == v.shape and v.grad.dtype == dtype
    single = st.unsigned_distance(torch.zeros(3, dtype=dtype), v, f)
    assert single.shape == () and single.dtype == dtype
    empty = st.signed_distance(torch.zeros(0, 3, dtype=dtype), v.detach(), f)
    assert empty.shape == (0,) and empty.dtype == dtype
    assert st.closest_points(torch.zeros(0, 3, dtype=dtype), v.detach(), f).shape == (0, 3)
    # Not contiguous: a transposed view gives the values of its copy.
    columns = points.detach().reshape(-1, 3).T.contiguous().T
    assert not columns.is_contiguous()
    assert torch.equal(st.signed_distance(columns, v.detach(), f), signed.detach().reshape(-1))


def test_float32_points_are_numpy_float32_and_gradients_are_float32(bunny):
    points = torch.rand(1000, 3, dtype=torch.float32) * 0.2 - 0.1
    points.requires_grad_(True)
    signed = st.signed_distance(points, bunny)
    assert torch.equal(signed.detach(), torch.from_numpy(bunny.signed_distance(points.detach().numpy())))
    signed.sum().backward()
    assert points.grad.dtype == torch.float32


def test_no_grad_and_no_inputs_requiring_grad():
    vertices, faces = MESHES["open"]
    points = torch.from_numpy(clear_points(vertices, faces, 10, seed=9))
    with torch.no_grad():
        with_grad_off = st.signed_distance(points.clone().requires_grad_(True), torch.from_numpy(vertices), torch.from_numpy(faces))
    assert not with_grad_off.requires_grad
    plain = st.signed_distance(points, torch.from_numpy(vertices), torch.from_numpy(faces))
    assert not plain.requires_grad and torch.equal(plain, with_grad_off)


def test_gradients_of_gradients_are_refused():
    mesh = sdfgen.Mesh(*MESHES["closed"])
    points = torch.tensor([[2.0, 0.3, 0.2]], dtype=torch.float64, requires_grad=True)
    for function in (st.signed_distance, st.closest_points):
        with pytest.raises(RuntimeError, match="first derivatives only"):
            torch.autograd.grad(function(points, mesh).sum(), points, create_graph=True)


def test_other_devices():
    vertices, faces = MESHES["closed"]
    with pytest.raises(ValueError, match="meta device"):
        st.signed_distance(torch.zeros(4, 3, device="meta"), sdfgen.Mesh(vertices, faces))
    if not torch.cuda.is_available():
        pytest.skip("no CUDA device: the round trip through another device is not exercised")
    points = torch.from_numpy(clear_points(vertices, faces, 16, seed=10)).cuda().requires_grad_(True)
    v = torch.from_numpy(vertices).cuda().requires_grad_(True)
    f = torch.from_numpy(faces).cuda()
    signed = st.signed_distance(points, v, f)
    assert signed.device == points.device
    signed.sum().backward()
    assert points.grad.device == points.device and v.grad.device == v.device
    cpu = st.signed_distance(points.detach().cpu(), v.detach().cpu(), f.cpu())
    assert torch.equal(signed.detach().cpu(), cpu)


def test_errors(bunny):
    points = torch.zeros(5, 3, dtype=torch.float64)
    v, f = torch.from_numpy(TET_VERTICES), torch.from_numpy(TET_FACES)
    with pytest.raises(ValueError, match=r"points must have shape \(\.\.\., 3\), not \(5, 2\)"):
        st.signed_distance(torch.zeros(5, 2), bunny)
    with pytest.raises(ValueError, match="points must be float32 or float64, not torch.int64"):
        st.unsigned_distance(torch.zeros(5, 3, dtype=torch.int64), bunny)
    with pytest.raises(ValueError, match="points must be a torch.Tensor"):
        st.closest_points(np.zeros((5, 3)), bunny)
    with pytest.raises(ValueError, match="vertices must have the points' dtype"):
        st.signed_distance(points, v.float(), f)
    with pytest.raises(ValueError, match=r"vertices must have shape \(V, 3\)"):
        st.signed_distance(points, v[:, :2], f)
    with pytest.raises(ValueError, match="faces must be an integer tensor"):
        st.signed_distance(points, v, f.double())
    with pytest.raises(ValueError, match=r"faces must have shape \(F, 3\)"):
        st.signed_distance(points, v, f[:, :2])
    with pytest.raises(ValueError, match="not both"):
        st.signed_distance(points, bunny, f)
    with pytest.raises(ValueError, match="an sdfgen.Mesh, or vertices and faces"):
        st.signed_distance(points, v)
    with pytest.raises(ValueError, match="sign must be auto, winding, pseudonormal"):
        st.signed_distance(points, bunny, sign="parity")
    with pytest.raises(sdfgen.Error, match="query point 1 has a non-finite coordinate"):
        st.signed_distance(torch.tensor([[0.0, 0, 0], [float("nan"), 0, 0]]), bunny)
    with pytest.raises(sdfgen.Error, match="face 0 has vertex index -1"):
        st.signed_distance(points, v, torch.tensor([[-1, 1, 2]]))
    with pytest.raises(sdfgen.Error, match="uses vertex 9"):
        st.signed_distance(points, v, torch.tensor([[0, 1, 8]]))


def test_batched_meshes_equal_single_calls_and_pass_gradcheck():
    # B = 3 octahedra moved apart, with the faces shared and with faces of their own (reordered).
    vertices, faces = MESHES["closed"]
    batch = torch.stack([torch.from_numpy(vertices * (1 + 0.1 * b) + 0.05 * b) for b in range(3)])
    own_faces = torch.stack([torch.from_numpy(np.roll(faces, b, axis=0)) for b in range(3)])
    points = torch.stack([torch.from_numpy(clear_points(vertices * (1 + 0.1 * b) + 0.05 * b, faces, 40, seed=b)) for b in range(3)])
    for f in (torch.from_numpy(faces), own_faces):
        for function in (st.signed_distance, st.unsigned_distance, st.closest_points):
            v, p = batch.clone().requires_grad_(), points.clone().requires_grad_()
            together = function(p, v, f)
            together.sum().backward()
            for b in range(3):
                vb, pb = batch[b].clone().requires_grad_(), points[b].clone().requires_grad_()
                alone = function(pb, vb, f if f.dim() == 2 else f[b])
                alone.sum().backward()
                assert torch.equal(together[b].detach(), alone.detach())
                assert torch.equal(p.grad[b], pb.grad) and torch.equal(v.grad[b], vb.grad)
    hit = st.closest(points, batch, own_faces)
    assert hit.triangle.shape == (3, 40) and hit.barycentric.shape == (3, 40, 3)
    assert torch.equal(hit.triangle[2], st.closest(points[2], batch[2], own_faces[2]).triangle)
    # Gradients to each mesh's vertices and points, against finite differences.
    v, p = batch[:2].clone().requires_grad_(), points[:2].clone().requires_grad_()
    assert torch.autograd.gradcheck(lambda p, v: st.signed_distance(p, v, own_faces[:2]), (p, v), eps=1e-7, atol=1e-6, rtol=1e-5)
    with pytest.raises(ValueError, match=r"take points of shape \(B, \.\.\., 3\) with B = 3"):
        st.signed_distance(points[:2], batch, own_faces)
    with pytest.raises(ValueError, match=r"take faces of shape \(F, 3\) or \(3, F, 3\)"):
        st.signed_distance(points, batch, own_faces[:2])


def single_and_batch(function, points, meshes, faces=None, **options):
    """Results and gradients of one batch call and of the single calls it stands for: lists of
    (result, points' gradient, vertices' gradient) per mesh."""
    def run(p, m, f, batch):
        p = [x.clone().requires_grad_() for x in p]
        m = [x if isinstance(x, sdfgen.Mesh) else x.clone().requires_grad_() for x in m]
        if batch:
            results = function(p, m, f, **options)
        else:
            results = [function(pb, mb, f if f is None or isinstance(f, torch.Tensor) else f[b], **options)
                       for b, (pb, mb) in enumerate(zip(p, m))]
        values = [r.distance if isinstance(r, sdfgen.ClosestHit) else r for r in results]
        sum(v.sum() for v in values).backward()
        return [(r, pb.grad, None if isinstance(mb, sdfgen.Mesh) else mb.grad) for r, pb, mb in zip(results, p, m)]
    return run(points, meshes, faces, True), run(points, meshes, faces, False)


def equal_results(mine, theirs):
    if isinstance(mine, sdfgen.ClosestHit):
        return all(torch.equal(a.detach(), b.detach()) for a, b in zip(mine, theirs))
    return torch.equal(mine.detach(), theirs.detach())


def test_lists_of_meshes_of_different_topology_equal_single_calls():
    # Three meshes of different sizes (octahedron, tetrahedron, open tetrahedron) with their own
    # numbers of points, then the bunny and an octahedron as Meshes: one call for each list, bit for
    # bit the single calls, gradients too.
    shapes = [MESHES["closed"], MESHES["closed-tetrahedron"], MESHES["open"]]
    vertices = [torch.from_numpy(v * (1 + 0.1 * b)) for b, (v, _) in enumerate(shapes)]
    faces = [torch.from_numpy(f) for _, f in shapes]
    points = [torch.from_numpy(clear_points(v.numpy(), f.numpy(), 20 + 10 * b, seed=b)) for b, (v, f) in enumerate(zip(vertices, faces))]
    for function in (st.signed_distance, st.unsigned_distance, st.closest_points, st.closest):
        together, alone = single_and_batch(function, points, vertices, faces)
        for (r, pg, vg), (r1, pg1, vg1) in zip(together, alone):
            assert equal_results(r, r1) and torch.equal(pg, pg1) and torch.equal(vg, vg1)
    inputs = tuple(x.clone().requires_grad_() for x in points[:2] + vertices[:2])
    assert torch.autograd.gradcheck(lambda p0, p1, v0, v1: torch.cat(st.signed_distance([p0, p1], [v0, v1], faces[:2])),
                                    inputs, eps=1e-7, atol=1e-6, rtol=1e-5)
    bunny = sdfgen.Mesh.load(BUNNY)
    octahedron = sdfgen.Mesh(*shapes[0])
    lo, hi = (np.array(b) for b in bunny.bounds)
    mesh_points = [torch.from_numpy(np.random.default_rng(4).uniform(lo, hi, (3000, 3))), points[0].float()]
    together, alone = single_and_batch(st.signed_distance, mesh_points, [bunny, octahedron])
    for (r, pg, _), (r1, pg1, _) in zip(together, alone):
        assert torch.equal(r.detach(), r1.detach()) and torch.equal(pg, pg1)
    with pytest.raises(ValueError, match="a list of 2 meshes takes a list of 2 points tensors, not 1 points"):
        st.signed_distance(mesh_points[:1], [bunny, octahedron])
    with pytest.raises(ValueError, match="all sdfgen.Mesh or all vertices tensors"):
        st.signed_distance(points[:2], [bunny, vertices[1]], faces[1])
    with pytest.raises(ValueError, match="a list of 3 vertices takes a list of 3 faces tensors or one shared, not 2 faces"):
        st.signed_distance(points, vertices, faces[:2])


def test_batches_refit_step_to_step_and_answer_large_ones_alone():
    # A (B, V, 3) batch moved step by step refits each mesh (one batch kept), equal to fresh
    # builds; a batch mixing a mesh of many points (answered alone on every thread) with small ones.
    vertices, faces = MESHES["closed"]
    f = torch.from_numpy(faces)
    points = torch.stack([torch.from_numpy(clear_points(vertices, faces, 40, seed=b)) for b in range(4)])
    st._tensor_batches.clear()
    for step in range(3):
        batch = torch.stack([torch.from_numpy(vertices * (1 + 0.01 * step + 0.1 * b)) for b in range(4)])
        refit = st.signed_distance(points, batch, f)
        assert len(st._tensor_batches) == 1
        kept = list(st._tensor_batches)
        st._tensor_batches.clear()
        assert torch.equal(refit, st.signed_distance(points, batch, f))  # built afresh
        st._tensor_batches[:] = kept
    many = torch.from_numpy(np.random.default_rng(5).uniform(-1.2, 1.2, (20000, 3)))
    lists = [many, points[0], points[1]]
    meshes = [torch.from_numpy(vertices * (1 + 0.1 * b)) for b in range(3)]
    for mine, theirs in zip(st.closest(lists, meshes, f), [st.closest(p, v, f) for p, v in zip(lists, meshes)]):
        assert equal_results(mine, theirs)


def test_a_batch_warns_once_per_mesh():
    # Each mesh's warnings (here a zero-area triangle dropped) reach Python once, from the calling thread.
    vertices = torch.from_numpy(np.vstack([TET_VERTICES, [[2.0, 2.0, 2.0]]]))
    faces = torch.from_numpy(np.vstack([TET_FACES, [[0, 0, 4]]]))
    points = [torch.from_numpy(clear_points(TET_VERTICES, TET_FACES, 5, seed=b)) for b in range(2)]
    with pytest.warns(sdfgen.Warning) as caught:
        st.signed_distance(points, [vertices, vertices * 2], [faces, faces])
    assert [str(w.message) for w in caught] == ["<tensors>: dropped 1 zero-area triangles"] * 2
