"""Small point calls (fewer than 2048 points, threads=0) run on the calling thread alone: no watcher
thread, no worker pool started, so 100 points cost microseconds, not a pool's wake-up
(bench/python_bench.py --small-calls times it). Checked by the process's thread count, which
timing on a shared machine could not show reliably. Run by ctest (label python)."""
import os
import subprocess
import sys
import textwrap

SCRIPT = textwrap.dedent("""
    import os, numpy as np, sdfgen
    def threads():
        with open("/proc/self/status") as f:
            return next(int(line.split()[1]) for line in f if line.startswith("Threads:"))
    root = os.environ["SDFGEN_SOURCE_DIR"]
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    mesh = sdfgen.Mesh(vertices, faces, threads=1)
    points = np.random.default_rng(0).uniform(-0.5, 1.5, size=(100, 3))
    before = threads()
    for _ in range(50):
        mesh.signed_distance(points); mesh.closest_points(points); mesh.winding_number(points)
        sdfgen.sample(mesh, 100, seed=1)
    small = threads()
    big = np.random.default_rng(1).uniform(-0.5, 1.5, size=(100_000, 3))
    assert np.array_equal(mesh.signed_distance(big)[:100], mesh.signed_distance(big[:100]))
    print(before, small, threads())
""")


def test_small_calls_start_no_threads():
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
           "SDFGEN_SOURCE_DIR": os.environ.get("SDFGEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))}
    result = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    before, small, after_big = map(int, result.stdout.split())
    assert small == before, f"small calls started {small - before} threads"
    if (os.cpu_count() or 1) > 1:
        assert after_big > before  # the large call did use the pool: the count shows it
