"""The sdfgen Python module: meshes from files and arrays, bakes with zero-copy values, point
queries that reproduce the baked values exactly, DeepSDF-style samples, errors, the GIL and Ctrl+C.
Run by ctest (label python) with PYTHONPATH=build/python and SDFGEN_SOURCE_DIR set."""
import gc
import os
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import sdfgen

ROOT = os.environ.get("SDFGEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUNNY = os.path.join(ROOT, "assets", "bunny.obj")

# A closed tetrahedron and the same without its base (open: auto signs by the winding number).
TET_VERTICES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32)


def box_mesh(half):
    """An axis-aligned box about the origin, two counter-clockwise triangles per face."""
    corners = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], dtype=np.float64) * half
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    faces = [tri for a, b, c, d in quads for tri in ((a, b, c), (a, c, d))]
    return corners, np.array(faces, dtype=np.int64)


def box_distance(points, half):
    q = np.abs(points) - half
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
    inside = np.minimum(np.max(q, axis=-1), 0.0)
    return outside + inside


@pytest.fixture(scope="module")
def bunny():
    return sdfgen.Mesh.load(BUNNY)


@pytest.fixture(scope="module")
def box():
    half = np.array([1.0, 0.5, 0.25])
    return sdfgen.Mesh(*box_mesh(half), name="box"), half


def test_mesh_from_file(bunny):
    assert bunny.triangle_count == 3674
    assert bunny.vertices.shape[1] == 3 and bunny.vertices.dtype == np.float64
    assert bunny.faces.shape == (3674, 3) and bunny.faces.dtype == np.int64
    check = bunny.check()
    assert check["closed_and_clean"] is True
    assert check["boundary_edges"] == 0
    assert "boundary edges" in check["description"]
    lo, hi = bunny.bounds
    assert np.all(np.array(lo) < np.array(hi))


def test_mesh_from_arrays_float32_and_float64():
    double = sdfgen.Mesh(TET_VERTICES, TET_FACES)
    single = sdfgen.Mesh(TET_VERTICES.astype(np.float32), TET_FACES.astype(np.uint32))
    points = np.random.default_rng(1).uniform(-0.5, 1.5, size=(500, 3))
    assert np.array_equal(double.signed_distance(points), single.signed_distance(points))
    assert double.check()["closed_and_clean"] is True
    opened = sdfgen.Mesh(TET_VERTICES, TET_FACES[1:])
    assert opened.check()["boundary_edges"] == 3
    assert opened.check()["self_intersections"] == 0
    baked = sdfgen.bake(opened, res=8)
    assert baked.sign == "auto/winding"  # the holes decide: the self-intersection search is skipped
    assert baked.check["boundary_edges"] == 3 and baked.check["self_intersections"] is None
    assert np.array_equal(double.vertices, TET_VERTICES)


def test_bake_on_the_gpu_equals_the_cpu(bunny):
    cpu = sdfgen.bake(bunny, res=16, sign="winding", device="cpu")
    assert cpu.device == "cpu: asked for"
    with pytest.raises(ValueError, match="device must be cpu, gpu or auto"):
        sdfgen.bake(bunny, res=8, device="tpu")
    try:
        gpu = sdfgen.bake(bunny, res=16, sign="winding", device="gpu")
    except sdfgen.Error as e:  # no OpenGL 4.5 here, or a module built without the renderer
        pytest.skip(str(e))
    assert gpu.device.startswith("gpu: GL vendor")
    assert np.max(np.abs(np.abs(gpu.values) - np.abs(cpu.values))) <= 1e-4 * cpu.voxel_size
    assert np.array_equal(np.signbit(gpu.values), np.signbit(cpu.values))


def test_bake_values_are_a_fortran_view_kept_alive(bunny):
    field = sdfgen.bake(bunny, res=24)
    values = field.values
    assert values.shape == field.dims and values.dtype == np.float32
    assert values.flags.f_contiguous and not values.flags.owndata
    assert field.values.__array_interface__["data"][0] == values.__array_interface__["data"][0]  # no copy
    nx, ny, nz = field.dims
    assert max(field.dims) == 24 and field.voxel_size > 0
    assert field.sign == "auto/pseudonormal" and "closed" in field.sign_reason
    assert field.check["closed_and_clean"] is True
    expected = values.copy()
    del field
    gc.collect()
    assert np.array_equal(values, expected)  # the view keeps the field's buffer alive
    assert values.min() < 0 < values.max()


def test_positions_are_the_sample_positions(box):
    mesh, half = box
    field = sdfgen.bake(mesh, res=10, padding=0.2)
    p = field.positions()
    assert p.shape == field.dims + (3,) and p.dtype == np.float64
    i, j, k = 3, 1, 2
    expected = np.array(field.origin) + (np.array([i, j, k]) + 0.5) * field.voxel_size
    assert np.allclose(p[i, j, k], expected, rtol=0, atol=1e-12)  # the library may fuse the multiply-add


@pytest.mark.parametrize("faces", [TET_FACES, TET_FACES[1:]], ids=["closed", "open"])
def test_signed_distance_at_positions_is_exactly_the_field(faces):
    mesh = sdfgen.Mesh(TET_VERTICES, faces)
    field = sdfgen.bake(mesh, res=20)
    assert field.sign == ("auto/pseudonormal" if len(faces) == 4 else "auto/winding")
    assert np.array_equal(mesh.signed_distance(field.positions()), field.values)


def test_signed_distance_at_bunny_positions_is_exactly_the_field(bunny):
    field = sdfgen.bake(bunny, res=32, sign="winding")
    assert np.array_equal(bunny.signed_distance(field.positions(), sign="winding"), field.values)


def test_queries_against_the_analytic_box(box):
    mesh, half = box
    points = np.random.default_rng(2).uniform(-1.5, 1.5, size=(4000, 3))
    truth = box_distance(points, half)
    sdf = mesh.signed_distance(points)
    assert sdf.dtype == np.float32 and sdf.shape == (4000,)
    assert np.max(np.abs(sdf - truth)) < 1e-6
    assert np.array_equal(mesh.unsigned_distance(points), np.abs(sdf))
    closest = mesh.closest_points(points)
    assert closest.shape == (4000, 3)
    assert np.max(np.abs(np.linalg.norm(points - closest, axis=1) - np.abs(truth))) < 1e-6
    winding = mesh.winding_number(points)
    assert np.all(np.abs(winding[truth < -1e-3] - 1.0) < 1e-9) and np.all(np.abs(winding[truth > 1e-3]) < 1e-9)
    nearest = mesh.nearest_triangle(points)
    assert nearest.dtype == np.int64 and nearest.min() >= 0 and nearest.max() < mesh.triangle_count
    # Any leading shape (..., 3) works.
    assert mesh.signed_distance(points.reshape(20, 200, 3)).shape == (20, 200)


def test_sample_exact_count_reproducible_and_consistent(bunny):
    points, sdf = sdfgen.sample(bunny, 10001, seed=7, threads=1)
    assert points.shape == (10001, 3) and points.dtype == np.float32
    assert sdf.shape == (10001,) and sdf.dtype == np.float32
    again, sdf_again = sdfgen.sample(bunny, 10001, seed=7, threads=3)
    assert np.array_equal(points, again) and np.array_equal(sdf, sdf_again)
    other, _ = sdfgen.sample(bunny, 10001, seed=8)
    assert not np.array_equal(points, other)
    assert np.array_equal(bunny.signed_distance(points), sdf)


def test_sample_distribution_follows_deepsdf(box):
    mesh, half = box
    n = 40000
    points, sdf = sdfgen.sample(mesh, n, seed=3)
    near = int(round(n * 47 / 50))
    first, second = (near + 1) // 2, near // 2
    radius = 1.03 * np.linalg.norm(half)  # farthest vertex from the box centre, with DeepSDF's buffer
    # Near a flat face, the signed distance of surface point + noise is the noise's normal component.
    for group, variance in ((sdf[:first], 0.0025), (sdf[first:near], 0.00025)):
        sigma = np.sqrt(variance) * radius
        assert abs(np.median(np.abs(group)) / (0.6745 * sigma) - 1.0) < 0.1
    uniform = points[near:]
    pad = 0.1 * 2.0
    assert np.all(uniform >= -half - pad - 1e-6) and np.all(uniform <= half + pad + 1e-6)
    assert np.all(uniform.max(axis=0) > half + pad * 0.9)
    everything_near, _ = sdfgen.sample(mesh, 100, surface_fraction=1.0, wide_variance=0.0, narrow_variance=0.0)
    assert np.max(np.abs(box_distance(everything_near.astype(np.float64), half))) < 1e-6


def test_errors_carry_the_one_line_message(tmp_path):
    with pytest.raises(sdfgen.Error, match="missing.obj"):
        sdfgen.Mesh.load(str(tmp_path / "missing.obj"))
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(sdfgen.Error, match=r"broken.obj:2: vertex coordinate 'nan' is not a finite number"):
        sdfgen.Mesh.load(str(broken))
    assert issubclass(sdfgen.Error, RuntimeError)
    with pytest.raises(sdfgen.Error, match="mine: face 0 has vertex index -1"):
        sdfgen.Mesh(TET_VERTICES, np.array([[0, 1, -1]]), name="mine")
    with pytest.raises(sdfgen.Error, match="uses vertex 10"):
        sdfgen.Mesh(TET_VERTICES, np.array([[0, 1, 9]]))
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        sdfgen.Mesh(TET_VERTICES[:, :2], TET_FACES)
    with pytest.raises(ValueError, match="integer"):
        sdfgen.Mesh(TET_VERTICES, TET_FACES.astype(np.float64))
    mesh = sdfgen.Mesh(TET_VERTICES, TET_FACES)
    with pytest.raises(ValueError, match=r"res must be from 1 to 65536 voxels along the longest side \(got 0\)"):
        sdfgen.bake(mesh, res=0)
    with pytest.raises(ValueError, match="sign must be"):
        sdfgen.bake(mesh, sign="sideways")
    with pytest.raises(ValueError, match=r"\(P, 3\)"):
        mesh.signed_distance(np.zeros((4, 2)))
    bad = tmp_path / "bad.sdf"
    bad.write_text("not a field\n")
    with pytest.raises(sdfgen.Error, match="bad.sdf"):
        sdfgen.load_field(str(bad))


def test_threads_are_limited_like_the_command_line(bunny):
    # --threads takes 0..1024; so does every call here (TBB cannot set up an arena of 100000).
    for threads in (100000, 1025, -1):
        with pytest.raises(sdfgen.Error, match="threads must be from 0 \\(all cores\\) to 1024, not " + str(threads)):
            sdfgen.Mesh(TET_VERTICES, TET_FACES, threads=threads)
        with pytest.raises(sdfgen.Error, match="threads must be"):
            sdfgen.bake(bunny, res=8, threads=threads)
        with pytest.raises(sdfgen.Error, match="threads must be"):
            bunny.signed_distance(np.zeros((1, 3)), threads=threads)
        with pytest.raises(sdfgen.Error, match="threads must be"):
            sdfgen.sample(bunny, 10, threads=threads)
    assert bunny.signed_distance(np.zeros((1, 3)), threads=1024).shape == (1,)


def test_far_points_are_refused_not_answered_wrongly(bunny):
    lo, hi = (np.array(b) for b in bunny.bounds)
    size = np.max(hi - lo)
    near = np.array([[hi[0] + 9000 * size, 0.0, 0.0]])
    assert bunny.signed_distance(near)[0] > 0
    with pytest.raises(sdfgen.Error, match=r"bunny.obj: query point 0 \(1e\+300, 0, 0\) is .* mesh sizes from the mesh's bounding box"):
        bunny.signed_distance(np.array([[1e300, 0.0, 0.0]]))


def test_unsigned_face_indices_are_shown_as_they_are():
    faces = TET_FACES.astype(np.uint64)
    faces[1, 2] = np.uint64(2**64 - 1)
    with pytest.raises(sdfgen.Error, match="face 1 has vertex index 18446744073709551615, outside 0..3"):
        sdfgen.Mesh(TET_VERTICES, faces, name="unsigned")


def test_warnings_are_issued_as_sdfgen_warnings(tmp_path):
    assert issubclass(sdfgen.Warning, UserWarning)
    # Two zero-area triangles: dropped, with a warning at the load.
    degenerate = tmp_path / "degenerate.obj"
    degenerate.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 1 2\nf 2 3 3\n")
    with pytest.warns(sdfgen.Warning, match="degenerate.obj: dropped 2 zero-area triangles"):
        mesh = sdfgen.Mesh.load(str(degenerate))
    assert mesh.dropped_degenerate == 2
    # A bake's warnings, also kept on the field: a pseudonormal sign asked for on a mesh inside out.
    inverted = sdfgen.Mesh(TET_VERTICES, TET_FACES[:, ::-1].copy(), name="inverted")
    with pytest.warns(sdfgen.Warning, match="inverted: the mesh is inside out") as record:
        field = sdfgen.bake(inverted, res=8, sign="pseudonormal")
    assert field.warnings and all("inverted: " + w in [str(r.message) for r in record] for w in field.warnings)
    assert sdfgen.bake(sdfgen.Mesh(TET_VERTICES, TET_FACES), res=8).warnings == []
    # A filter can make them errors.
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", sdfgen.Warning)
        with pytest.raises(sdfgen.Warning):
            sdfgen.Mesh.load(str(degenerate))


def test_hostile_field_files_raise_sdfgen_error(tmp_path):
    # A voxel size below float32's normal range, and a .vdb whose transform is NaN (OpenVDB's own
    # exceptions must not leak as a plain RuntimeError): sdfgen.Error naming the file, one line.
    denormal = tmp_path / "denormal.sdf"
    denormal.write_text("sdfgen-text 1\nsource s\ndims 1 1 1\norigin 0 0 0\nvoxel 1e-320\nmethod m\nvalues\n0\n")
    with pytest.raises(sdfgen.Error, match=r"denormal.sdf: voxel size 1e-320 is not a positive normal float32"):
        sdfgen.load_field(str(denormal))
    mesh = sdfgen.Mesh(TET_VERTICES, TET_FACES)
    path = tmp_path / "tet.vdb"
    sdfgen.bake(mesh, res=6).save(str(path))
    data = bytearray(path.read_bytes())
    at = data.find(b"UniformScaleTranslateMap") + len("UniformScaleTranslateMap")
    data[at : at + 8] = np.array([np.nan]).tobytes()
    path.write_bytes(bytes(data))
    with pytest.raises(sdfgen.Error, match="tet.vdb: ") as error:
        sdfgen.load_field(str(path))
    assert type(error.value) is sdfgen.Error and "\n" not in str(error.value)


@pytest.mark.parametrize("extension", [".sdf", ".npz"])
def test_save_and_load_round_trip(tmp_path, extension):
    mesh = sdfgen.Mesh(TET_VERTICES, TET_FACES)
    field = sdfgen.bake(mesh, res=12)
    path = str(tmp_path / ("tet" + extension))
    field.save(path)
    loaded = sdfgen.load_field(path)
    assert loaded.dims == field.dims and loaded.voxel_size == field.voxel_size and loaded.origin == field.origin
    assert np.array_equal(loaded.values, field.values)
    if extension == ".npz":
        archive = np.load(path)
        assert np.array_equal(archive["sdf"], field.values)


def test_progress_and_cancel_from_the_callback(bunny):
    seen = []
    sdfgen.bake(bunny, res=48, progress=seen.append)
    assert seen and seen[-1] == 1.0 and all(a <= b for a, b in zip(seen, seen[1:]))

    class Stop(Exception):
        pass

    def stop(fraction):
        raise Stop()

    start = time.monotonic()
    with pytest.raises(Stop):
        sdfgen.bake(bunny, res=200, progress=stop)
    assert time.monotonic() - start < 5.0


def test_long_calls_release_the_gil(bunny):
    result = {}

    def work():
        start = time.monotonic()
        result["field"] = sdfgen.bake(bunny, res=96)
        result["seconds"] = time.monotonic() - start

    thread = threading.Thread(target=work)
    spins = 0
    thread.start()
    while thread.is_alive():
        spins += 1  # Python keeps running while the bake does
    thread.join()
    assert result["seconds"] > 0.05
    assert spins > 10000, f"only {spins} iterations of the Python loop ran during a {result['seconds']:.2f} s bake"
    # Queries from several threads at once on one mesh.
    points = np.random.default_rng(4).uniform(-0.1, 0.1, size=(20000, 3))
    expected = bunny.signed_distance(points)
    outputs = [None] * 4

    def query(i):
        outputs[i] = bunny.signed_distance(points)

    threads = [threading.Thread(target=query, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(o, expected) for o in outputs)


def test_ctrl_c_cancels_a_bake():
    script = textwrap.dedent(
        f"""
        import os, signal, threading, time
        import sdfgen
        mesh = sdfgen.Mesh.load({BUNNY!r})
        threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        start = time.monotonic()
        try:
            sdfgen.bake(mesh, res=400)
            print("finished")
        except KeyboardInterrupt:
            print("interrupted after", time.monotonic() - start)
        """
    )
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, env=os.environ)
    assert run.returncode == 0, run.stderr
    words = run.stdout.split()
    assert words[:2] == ["interrupted", "after"], run.stdout
    assert float(words[2]) < 3.0


def test_points_and_vertices_must_be_real_numbers(bunny):
    # A cast to float64 would drop the imaginary part, or read bools as 0 and 1.
    for dtype in (np.complex128, np.bool_):
        with pytest.raises(ValueError, match="points must be real numbers"):
            bunny.signed_distance(np.zeros((2, 3), dtype))
        with pytest.raises(ValueError, match="vertices must be real numbers"):
            sdfgen.Mesh(TET_VERTICES.astype(dtype), TET_FACES)
    with pytest.raises(ValueError, match="points must be real numbers"):
        bunny.closest_points(np.array([[1 + 2j, 0, 0]]))
    with pytest.raises(ValueError, match="points must be real numbers"):
        bunny.signed_distance(np.array([["a", "b", "c"]]))
    # Integers are numbers, as documented: the same answers as floats.
    assert np.array_equal(bunny.signed_distance(np.array([[0, 0, 0], [1, 2, 3]])),
                          bunny.signed_distance(np.array([[0.0, 0, 0], [1, 2, 3]])))
    ints = sdfgen.Mesh(TET_VERTICES.astype(np.int32), TET_FACES)
    assert ints.signed_distance(np.array([[0.25, 0.25, 0.25]]))[0] < 0


def test_argument_errors_are_one_line(bunny):
    for call in (lambda: sdfgen.bake(bunny, res="high"), lambda: sdfgen.bake(bunny, 8, bogus=1),
                 lambda: bunny.signed_distance(np.zeros((1, 3)), threads="all"), lambda: sdfgen.Mesh.load(42),
                 lambda: sdfgen.Mesh(np.zeros((3, 3)), TET_FACES, name=7), lambda: sdfgen.load_field(None)):
        with pytest.raises(TypeError) as error:
            call()
        message = str(error.value)
        assert "\n" not in message, message
        assert "do not match" in message and "sdfgen." in message, message
    with pytest.raises(TypeError, match=r"^sdfgen.bake\(\): the arguments \(.*'high'.*\) do not match \(mesh: sdfgen.Mesh"):
        sdfgen.bake(bunny, res="high")


def test_messages_escape_bytes_that_are_not_utf8(tmp_path):
    # An overlong NUL (C0 80) and a surrogate (ED A0 80): escaped, so that the message decodes.
    bad = tmp_path / "bad.ply"
    bad.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty fl\xc0\x80\xed\xa0\x80 x\nend_header\n")
    with pytest.raises(sdfgen.Error, match=r"bad.ply:4: unknown property type 'fl\\xc0\\x80\\xed\\xa0\\x80'"):
        sdfgen.Mesh.load(str(bad))
