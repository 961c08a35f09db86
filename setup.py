"""Builds the sdfgen package for pip (pyproject.toml): the compiled module by CMake, in a build
folder of its own (build-python/), without the viewer or the tests; the module, libsdfgen and its
plugin libraries go into the package folder together (CMake's install component python_wheel).
Needs what the CMake build needs (scripts/setup.sh installs it on Debian); CMAKE_ARGS in the
environment adds options to CMake's configure step."""
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
# CMake's build folder, one level below the source like the usual build/, so that ccache (which
# sees paths relative to it) reuses the objects of a CMake build of the same sources.
CMAKE_BUILD = ROOT / "build-python"


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        try:
            import numpy  # noqa: F401
        except ImportError:
            raise SystemExit(f"sdfgen: {sys.executable} has no numpy, which the module needs (nothing is fetched from PyPI). "
                             "Make the venv from Debian's interpreter, whose python3-numpy it then sees: "
                             "/usr/bin/python3 -m venv --system-site-packages ENV") from None
        package_root = Path(self.get_ext_fullpath(ext.name)).resolve().parent.parent  # the folder holding sdfgen/
        configure = ["cmake", "-S", str(ROOT), "-B", str(CMAKE_BUILD), "-DCMAKE_BUILD_TYPE=Release", "-DSDFGEN_VIEWER=OFF",
                     "-DSDFGEN_BUILD_TESTS=OFF", "-DSDFGEN_PYTHON=ON", "-DSDFGEN_PYTHON_WHEEL=ON",
                     f"-DPython_EXECUTABLE={sys.executable}", *shlex.split(os.environ.get("CMAKE_ARGS", ""))]
        if not (CMAKE_BUILD / "CMakeCache.txt").exists() and shutil.which("ninja"):
            configure += ["-G", "Ninja"]
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(CMAKE_BUILD), "--target", "sdfgen_python", "--parallel", jobs], check=True)
        subprocess.run(["cmake", "--install", str(CMAKE_BUILD), "--component", "python_wheel", "--prefix", str(package_root)],
                       check=True)


def version():
    """The project's version, from CMakeLists.txt's project()."""
    return re.search(r"project\(sdfgen VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text()).group(1)


setup(
    version=version(),
    ext_modules=[Extension("sdfgen._sdfgen", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(CMAKE_BUILD / "setuptools")}},
)
