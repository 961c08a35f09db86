"""Mesh.with_vertices and sdfgen.torch's meshes from tensors whose vertices move (optimisation
steps): the tree is refit and the check kept, and every answer (queries, the closest-hit record,
bakes, torch values and gradients) equals that of a mesh built afresh from the moved vertices.
Run by ctest (label python) with PYTHONPATH=build/python and SDFGEN_SOURCE_DIR set."""
import numpy as np
import pytest

import sdfgen


def icosphere(levels):
    """A unit icosphere: the icosahedron with each triangle split in four `levels` times (20 * 4^levels triangles)."""
    t = (1 + 5 ** 0.5) / 2
    vertices = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    vertices = [list(np.array(v) / np.linalg.norm(v)) for v in vertices]
    faces = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6],
             [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
             [8, 6, 7], [9, 8, 1]]
    for _ in range(levels):
        middle = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = np.add(vertices[a], vertices[b])
                vertices.append(list(m / np.linalg.norm(m)))
                middle[key] = len(vertices) - 1
            return middle[key]

        split = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            split += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        faces = split
    return np.array(vertices), np.array(faces, dtype=np.int64)


def wobble(vertices, step):
    """Smoothly moved vertices: no triangle folds or crosses another."""
    x, y, z = vertices.T
    return vertices + 0.02 * step * np.stack([np.sin(3 * y), np.cos(2 * z), np.sin(x + y)], axis=1)


def points_around(count, seed):
    return np.random.default_rng(seed).uniform(-1.5, 1.5, size=(count, 3))


def test_moved_mesh_answers_as_a_fresh_one():
    vertices, faces = icosphere(3)
    points = points_around(2000, seed=1)
    mesh = sdfgen.Mesh(vertices, faces)
    first_check = mesh.check()
    for step in range(1, 4):
        moved = wobble(vertices, step)
        mesh = mesh.with_vertices(moved)
        fresh = sdfgen.Mesh(moved, faces)
        assert mesh.check() == fresh.check() == first_check
        assert np.array_equal(mesh.vertices, fresh.vertices) and np.array_equal(mesh.faces, fresh.faces)
        for sign in ("auto", "winding", "pseudonormal"):
            assert np.array_equal(mesh.signed_distance(points, sign=sign), fresh.signed_distance(points, sign=sign))
            for mine, theirs in zip(mesh.closest(points, sign=sign), fresh.closest(points, sign=sign)):
                assert np.array_equal(mine, theirs)
        assert np.array_equal(mesh.winding_number(points), fresh.winding_number(points))
        assert np.array_equal(sdfgen.bake(mesh, res=24).values, sdfgen.bake(fresh, res=24).values)


def test_the_check_is_kept_and_a_changed_triangle_list_builds_afresh():
    vertices, faces = icosphere(2)
    mesh = sdfgen.Mesh(vertices, faces)
    assert mesh.check()["closed_and_clean"]
    pushed = vertices.copy()
    pushed[pushed[:, 1] > 0.5, 1] -= 1.2  # the cap pushed through the sphere: it crosses itself
    assert sdfgen.Mesh(pushed, faces).check()["self_intersections"] > 0
    assert mesh.with_vertices(pushed).check()["self_intersections"] == 0  # auto's decision kept, as documented
    # A triangle of zero area is dropped: the triangle list changes, so the mesh is built afresh.
    flat = wobble(vertices, 1)
    a, b, c = faces[0]
    flat[c] = flat[a]
    with pytest.warns(sdfgen.Warning, match="dropped 2 zero-area triangles"):
        moved, fresh = mesh.with_vertices(flat), sdfgen.Mesh(flat, faces)  # faces[0] and its neighbour over a-c
    assert moved.triangle_count == fresh.triangle_count == len(faces) - 2
    points = points_around(500, seed=2)
    assert np.array_equal(moved.signed_distance(points), fresh.signed_distance(points))


def unwelded(vertices, faces):
    """Every triangle with its own three vertices, as an OBJ exporter may write them: the vertices
    merged by position make the mesh closed."""
    return vertices[faces.reshape(-1)].copy(), np.arange(3 * len(faces), dtype=np.int64).reshape(-1, 3)


def assert_same_answers(mesh, fresh, points):
    assert mesh.check() == fresh.check()
    for sign in ("auto", "winding", "pseudonormal"):
        assert np.array_equal(mesh.signed_distance(points, sign=sign), fresh.signed_distance(points, sign=sign))
        for mine, theirs in zip(mesh.closest(points, sign=sign), fresh.closest(points, sign=sign)):
            assert np.array_equal(mine, theirs)
    assert np.array_equal(mesh.winding_number(points), fresh.winding_number(points))


def test_a_weld_that_parts_or_joins_builds_afresh():
    # Moved together, the copies of each vertex stay one merged vertex: the refit keeps the
    # connectivity. A seam opened or two vertices brought together change it: what a fresh build
    # checks and decides, not the kept check.
    welded_vertices, welded_faces = icosphere(2)
    vertices, faces = unwelded(welded_vertices, welded_faces)
    points = points_around(1500, seed=4)
    mesh = sdfgen.Mesh(vertices, faces)
    assert mesh.check()["closed_and_clean"]
    moved = wobble(vertices, 1)
    mesh = mesh.with_vertices(moved)
    assert_same_answers(mesh, sdfgen.Mesh(moved, faces), points)

    opened = moved.copy()
    opened[0] *= 1.05  # one of the copies of a vertex, out of its seam: a hole of two edges
    parted, fresh = mesh.with_vertices(opened), sdfgen.Mesh(opened, faces)
    assert fresh.check()["boundary_edges"] > 0
    assert_same_answers(parted, fresh, points)

    joined = moved.copy()
    # The copies of the vertex farthest from vertex 0 moved onto vertex 0: no triangle collapses,
    # but the two merged vertices become one (a pinch).
    far = np.argmax(np.linalg.norm(moved - moved[0], axis=1))
    joined[np.all(moved == moved[far], axis=1)] = moved[0]
    met, fresh = mesh.with_vertices(joined), sdfgen.Mesh(joined, faces)
    assert met.triangle_count == fresh.triangle_count == len(faces)
    assert fresh.check()["non_manifold_vertices"] > 0
    assert_same_answers(met, fresh, points)


def test_refit_chains_over_unsigned_then_signed_queries_and_float32():
    # A mesh that answered unsigned queries only has no topology to refit: its vertex groups are
    # found once and kept; signed queries later build the topology, which later steps refit.
    vertices, faces = icosphere(3)
    points = points_around(1000, seed=5)
    mesh = sdfgen.Mesh(vertices.astype(np.float32), faces)
    mesh.unsigned_distance(points)
    for step in range(1, 5):
        moved = wobble(vertices, step).astype(np.float32)
        mesh = mesh.with_vertices(moved)
        fresh = sdfgen.Mesh(moved, faces)
        if step < 3:
            assert np.array_equal(mesh.unsigned_distance(points), fresh.unsigned_distance(points))
        else:
            assert_same_answers(mesh, fresh, points)


def test_with_vertices_refuses_another_vertex_count():
    vertices, faces = icosphere(1)
    with pytest.raises(ValueError, match="vertices must be the mesh's 42 vertices"):
        sdfgen.Mesh(vertices, faces).with_vertices(vertices[:-1])


def test_torch_steps_refit_and_equal_fresh_meshes():
    torch = pytest.importorskip("torch", reason="torch is not installed (Debian: apt-get install python3-torch)")
    import sdfgen.torch as st

    vertices, faces = icosphere(3)
    f = torch.from_numpy(faces)
    points = torch.from_numpy(points_around(1000, seed=3))

    def step(v, fresh):
        if fresh:
            st._tensor_meshes.clear()
        v = v.clone().requires_grad_()
        p = points.clone().requires_grad_()
        distance = st.signed_distance(p, v, f)
        closest = st.closest_points(p, v, f)
        (distance.sum() + closest.sum()).backward()
        return distance.detach(), closest.detach(), p.grad, v.grad

    st._tensor_meshes.clear()
    step(torch.from_numpy(vertices), fresh=False)
    for k in range(1, 4):
        moved = torch.from_numpy(wobble(vertices, k))
        refit = step(moved, fresh=False)
        assert len(st._tensor_meshes) == 1  # one topology, its latest mesh
        for mine, theirs in zip(refit, step(moved, fresh=True)):
            assert torch.equal(mine, theirs)


def test_torch_faces_changed_in_place_build_afresh():
    torch = pytest.importorskip("torch", reason="torch is not installed (Debian: apt-get install python3-torch)")
    import sdfgen.torch as st

    vertices, faces = icosphere(2)
    f = torch.from_numpy(faces.copy())
    centre = vertices[faces[0]].mean(axis=0)
    points = torch.from_numpy(np.concatenate([points_around(300, seed=6), [0.9 * centre, 1.1 * centre]]))
    st._tensor_meshes.clear()
    st.signed_distance(points, torch.from_numpy(vertices), f)
    # The same tensor changed in place (triangle 0 replaced by a copy of triangle 1: a hole): the
    # mesh kept for the old faces must not serve it.
    f[0] = f[1]
    moved = torch.from_numpy(wobble(vertices, 1))
    mine = st.signed_distance(points, moved, f)
    assert len(st._tensor_meshes) == 2
    st._tensor_meshes.clear()
    assert torch.equal(mine, st.signed_distance(points, moved, f))
    assert not torch.equal(mine, st.signed_distance(points, moved, torch.from_numpy(faces)))  # the change shows
