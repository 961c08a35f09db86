"""sample(normalize=True) and Mesh.normalization(): DeepSDF's units (the bounding box's centre, the
mesh in the unit sphere with its 3% buffer); the variances' names, wide and narrow, and their old
names. Run by ctest (label python) with PYTHONPATH=build/python."""
import os
import warnings

import numpy as np
import pytest

import sdfgen

ROOT = os.environ.get("SDFGEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUNNY = os.path.join(ROOT, "assets", "bunny.obj")


@pytest.fixture(scope="module")
def bunny():
    return sdfgen.Mesh.load(BUNNY)


def test_normalization_is_deepsdfs(bunny):
    centre, scale = bunny.normalization()
    used = bunny.vertices[np.unique(bunny.faces)]
    lo, hi = used.min(axis=0), used.max(axis=0)
    assert np.allclose(centre, (lo + hi) / 2, rtol=0, atol=1e-12)
    assert scale == pytest.approx(1.03 * np.max(np.linalg.norm(used - centre, axis=1)), rel=1e-12)
    normalized = (used - centre) / scale
    assert np.max(np.linalg.norm(normalized, axis=1)) == pytest.approx(1 / 1.03, rel=1e-12)  # in the unit sphere


def test_normalized_samples_are_the_world_samples_mapped(bunny):
    centre, scale = bunny.normalization()
    world = sdfgen.sample(bunny, 20000, seed=5, channels="sdf,gradient,closest,triangle")
    unit = sdfgen.sample(bunny, 20000, seed=5, channels="sdf,gradient,closest,triangle", normalize=True)
    assert np.array_equal(unit[0], ((world[0].astype(np.float64) - centre) / scale).astype(np.float32))
    assert np.array_equal(unit[1], (world[1].astype(np.float64) / scale).astype(np.float32))
    assert np.array_equal(unit[2], world[2]) and np.array_equal(unit[4], world[4])  # gradients and triangles as they are
    assert np.array_equal(unit[3], ((world[3].astype(np.float64) - centre) / scale).astype(np.float32))
    assert np.max(np.abs(unit[0])) < 1.3  # the padded box, in the unit sphere's units
    # They are the distances of the normalized mesh (up to float32 rounding of the points and values).
    normalized_mesh = sdfgen.Mesh((bunny.vertices - centre) / scale, bunny.faces)
    expected = normalized_mesh.signed_distance(unit[0])
    assert np.max(np.abs(expected - unit[1])) < 1e-5


def test_noise_scales_are_wide_then_narrow(bunny):
    centre, scale = bunny.normalization()
    n = 20000
    points, sdf = sdfgen.sample(bunny, n, seed=1, normalize=True)
    near = int(round(n * 47 / 50))
    first, second = sdf[:(near + 1) // 2], sdf[(near + 1) // 2:near]
    # Roughly the noise's normal component: its spread follows sqrt(variance) in normalized units.
    assert np.median(np.abs(first)) > 2 * np.median(np.abs(second))
    assert np.median(np.abs(first)) == pytest.approx(0.6745 * np.sqrt(0.0025), rel=0.25)


def test_old_variance_names_still_work_with_a_deprecation_warning(bunny):
    new = sdfgen.sample(bunny, 1000, seed=2, wide_variance=0.01, narrow_variance=0.0001)
    with pytest.warns(DeprecationWarning, match="near_variance is now wide_variance"):
        with warnings.catch_warnings():
            warnings.simplefilter("always")
            old = sdfgen.sample(bunny, 1000, seed=2, near_variance=0.01, far_variance=0.0001)
    assert all(np.array_equal(a, b) for a, b in zip(new, old))
