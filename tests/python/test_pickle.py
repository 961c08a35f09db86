"""Meshes in a training loop: pickle, copy.deepcopy and torch.save/torch.load give a Mesh whose
every query is bit-identical to the original's, and a torch DataLoader with spawned workers queries
a Mesh in each worker. Run by ctest (label python) with PYTHONPATH=build/python."""
import copy
import os
import pickle
import warnings

import numpy as np
import pytest

import sdfgen

ROOT = os.environ.get("SDFGEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUNNY = os.path.join(ROOT, "assets", "bunny.obj")


def far_mesh():
    """A float32 tetrahedron far from the world origin (a local frame with a large origin and a
    power-of-two unit) with a zero-area triangle (dropped, and warned about)."""
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [2, 0, 0]], dtype=np.float32) * 0.125 + np.float32(1000.0)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 1, 4]], dtype=np.int64)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sdfgen.Warning)
        return sdfgen.Mesh(vertices, faces, name="far tetrahedron")


def points_around(mesh, count=5000, seed=1):
    lo, hi = (np.array(b) for b in mesh.bounds)
    pad = 0.2 * np.max(hi - lo)
    return np.random.default_rng(seed).uniform(lo - pad, hi + pad, size=(count, 3))


def assert_same_mesh(a, b):
    assert type(b) is sdfgen.Mesh and b is not a
    for name in ("source", "triangle_count", "vertex_count", "dropped_degenerate", "warnings", "bounds"):
        assert getattr(a, name) == getattr(b, name), name
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    points = points_around(a)
    for query in ("signed_distance", "unsigned_distance", "closest_points", "nearest_triangle", "winding_number"):
        x, y = getattr(a, query)(points), getattr(b, query)(points)
        assert x.dtype == y.dtype and x.tobytes() == y.tobytes(), query  # bit for bit
    for sign in ("winding", "pseudonormal"):
        assert a.signed_distance(points, sign=sign).tobytes() == b.signed_distance(points, sign=sign).tobytes()
    for x, y in zip(sdfgen.sample(a, 2000, seed=3), sdfgen.sample(b, 2000, seed=3)):
        assert x.tobytes() == y.tobytes()
    assert np.array_equal(sdfgen.bake(a, res=16).values, sdfgen.bake(b, res=16).values)
    assert a.check() == b.check()


@pytest.fixture(scope="module", params=["bunny", "far"])
def mesh(request):
    return sdfgen.Mesh.load(BUNNY) if request.param == "bunny" else far_mesh()


@pytest.mark.parametrize("protocol", [2, pickle.HIGHEST_PROTOCOL])
def test_pickle_round_trip_is_bit_identical(mesh, protocol):
    data = pickle.dumps(mesh, protocol=protocol)
    assert len(data) < 100 * mesh.vertex_count + 100 * mesh.triangle_count + 10_000  # the mesh, not the tree
    with warnings.catch_warnings():
        warnings.simplefilter("error", sdfgen.Warning)  # warned once, when first built; not again
        restored = pickle.loads(data)
    assert_same_mesh(mesh, restored)


def test_far_mesh_keeps_its_warning_and_dropped_triangle():
    mesh = far_mesh()
    assert mesh.dropped_degenerate == 1
    assert pickle.loads(pickle.dumps(mesh)).dropped_degenerate == 1


def test_copy_and_deepcopy(mesh):
    assert_same_mesh(mesh, copy.deepcopy(mesh))
    assert_same_mesh(mesh, copy.copy(mesh))
    inside_a_list = copy.deepcopy([mesh, {"mesh": mesh}])
    assert_same_mesh(mesh, inside_a_list[1]["mesh"])


def test_bad_state_is_refused():
    mesh = far_mesh()
    state = mesh.__getstate__()
    with pytest.raises(ValueError, match="version"):
        sdfgen.Mesh.__new__(sdfgen.Mesh).__setstate__((99,) + tuple(state[1:]))
    broken = list(state)
    broken[5] = broken[5][:-1]  # triangles cut short
    with pytest.raises(ValueError):
        sdfgen.Mesh.__new__(sdfgen.Mesh).__setstate__(tuple(broken))


torch = pytest.importorskip("torch", reason="torch is not installed (Debian: apt-get install python3-torch)")


def test_torch_save_and_load(mesh, tmp_path):
    path = tmp_path / "checkpoint.pt"
    torch.save({"mesh": mesh, "step": 7}, path)
    loaded = torch.load(path)
    assert loaded["step"] == 7
    assert_same_mesh(mesh, loaded["mesh"])


class QueryDataset(torch.utils.data.Dataset):
    """Each item: points around the mesh and their signed distances, queried in the worker."""

    def __init__(self, mesh, items):
        self.mesh, self.items = mesh, items

    def __len__(self):
        return self.items

    def __getitem__(self, index):
        points = points_around(self.mesh, count=1000, seed=index)
        info = torch.utils.data.get_worker_info()
        return torch.from_numpy(points), torch.from_numpy(self.mesh.signed_distance(points)), os.getpid(), info.id if info else -1


def test_dataloader_with_spawned_workers_queries_in_each_worker():
    mesh = sdfgen.Mesh.load(BUNNY)
    loader = torch.utils.data.DataLoader(QueryDataset(mesh, 8), batch_size=None, num_workers=2,
                                         multiprocessing_context="spawn")
    pids, workers = set(), set()
    for index, (points, sdf, pid, worker) in enumerate(loader):
        expected = mesh.signed_distance(points.numpy())
        assert sdf.numpy().tobytes() == expected.tobytes()
        pids.add(int(pid))
        workers.add(int(worker))
    assert index == 7
    assert workers == {0, 1} and os.getpid() not in pids and len(pids) == 2
