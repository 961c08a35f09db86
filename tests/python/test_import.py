"""The package without its compiled module (a build that made only the command line, as ./run.sh
does) says so and how to build it, instead of Python's misleading "circular import" message."""
import os
import shutil
import subprocess
import sys

import sdfgen


def test_missing_compiled_module_is_named(tmp_path):
    package = tmp_path / "sdfgen"
    package.mkdir()
    here = os.path.dirname(sdfgen.__file__)
    for name in os.listdir(here):
        if name.endswith(".py"):
            shutil.copy(os.path.join(here, name), package / name)
    result = subprocess.run([sys.executable, "-c", "import sdfgen"], cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(tmp_path)},
                            capture_output=True, text=True)
    assert result.returncode != 0
    message = result.stderr.strip().splitlines()[-1]
    assert message.startswith("ImportError: sdfgen's compiled module (_sdfgen) is missing from"), message
    assert "--target sdfgen_python" in message and "circular" not in result.stderr
