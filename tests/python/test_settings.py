"""One check of the bake settings for every front end (sdfgen::problem): Python raises ValueError
with the message that `sdfgen bake` prints after the option's name, before any work; every limit
is refused, and every value just within it accepted, by both alike. The command line is
SDFGEN_CLI (set by ctest); its part is skipped without it."""
import math
import os
import re
import subprocess
import time

import numpy as np
import pytest

import sdfgen

TET_VERTICES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32)
CLI = os.environ.get("SDFGEN_CLI")

# Settings past a limit or that do not go together, and those just within the limits, as Python
# keywords (the settings' names; the command line's options are the same names with --).
REFUSED = [
    dict(res=0), dict(res=-3), dict(res=65537),
    dict(padding=-0.001), dict(padding=100.001), dict(padding=math.nan), dict(padding=math.inf),
    dict(rays=0), dict(rays=65537), dict(rays=10**8),
    dict(band=0.5), dict(band=-1.0), dict(band=math.nan), dict(band=math.inf), dict(band=1e9 + 1),
    dict(method="brute", sign="rays"),
    dict(method="rays", device="gpu"),
    dict(method="rays", band=2.0),
    dict(band=2.0, device="gpu"),
    dict(band=2.0, sign="rays"),
    dict(method="rays", channels="gradient"),
    dict(channels="closest", device="gpu"),
]
ACCEPTED = [dict(res=1), dict(padding=0.0), dict(padding=100.0), dict(rays=1), dict(rays=65536, method="exact"), dict(band=1.0)]


@pytest.fixture(scope="module")
def tet():
    return sdfgen.Mesh(TET_VERTICES, TET_FACES, name="tet")


def python_problem(mesh, settings):
    """The ValueError's message for these settings, None when the bake runs."""
    try:
        sdfgen.bake(mesh, **{"res": 4, "rays": 4, **settings})
    except ValueError as e:
        return str(e)
    return None


def cli_problem(tmp_path, settings):
    """The message `sdfgen bake` refuses these settings with (after "sdfgen: --OPTION: "), None when
    it bakes."""
    mesh = tmp_path / "tet.obj"
    if not mesh.exists():
        mesh.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in TET_VERTICES) +
                        "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in TET_FACES))
    options = []
    for name, value in {"res": 4, "rays": 4, **settings}.items():
        options += [f"--{name}", repr(value) if isinstance(value, float) and math.isfinite(value) else str(value)]
    run = subprocess.run([CLI, "bake", str(mesh), "-o", str(tmp_path / "out.npz"), *options], capture_output=True, text=True, timeout=60)
    if run.returncode == 0:
        return None
    match = re.fullmatch(r"sdfgen: --(\w+): (.*)\n", run.stderr)
    assert match, f"{settings}: not a settings problem: {run.stderr!r}"
    return match.group(2)


def test_rays_1e8_is_refused_before_any_work(tet):
    start = time.monotonic()
    with pytest.raises(ValueError, match=r"^rays must be from 1 to 65536 per sample \(got 100000000\)$"):
        sdfgen.bake(tet, res=64, method="rays", rays=10**8)
    assert time.monotonic() - start < 1.0


def test_each_limit_is_refused_and_just_within_it_accepted(tet):
    for settings in REFUSED:
        assert python_problem(tet, settings) is not None, settings
    for settings in ACCEPTED:
        assert python_problem(tet, settings) is None, settings


@pytest.mark.skipif(not CLI, reason="SDFGEN_CLI (the sdfgen binary) is not set")
def test_the_command_line_gives_the_same_answer(tet, tmp_path):
    for settings in REFUSED + ACCEPTED:
        assert cli_problem(tmp_path, settings) == python_problem(tet, settings), settings
