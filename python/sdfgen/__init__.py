"""sdfgen: exact signed distance fields, point queries and DeepSDF-style samples from triangle meshes.

Meshes (Mesh.load, Mesh(vertices, faces)), bakes (bake, load_field: a Field, or a SparseField for
a narrow band), point queries (the Mesh's methods) and samples (sample) take and give numpy arrays; sdfgen.torch gives the same queries on
torch tensors, with gradients (``import sdfgen.torch``; importing sdfgen alone never loads torch).
"""
import functools as _functools
import glob as _glob
import os as _os
import re as _re

try:
    from . import _sdfgen
except ImportError as _error:
    _here = _os.path.dirname(_os.path.abspath(__file__))
    if _glob.glob(_os.path.join(_here, "_sdfgen*.so")) or _glob.glob(_os.path.join(_here, "_sdfgen*.pyd")):
        raise  # the module is there but does not load: its own message says why
    # Python's own message would blame a circular import.
    raise ImportError(
        f"sdfgen's compiled module (_sdfgen) is missing from {_here}: the package's Python files are laid out but the "
        "module was not built (./run.sh builds only the command line). Build it with "
        "`cmake --build build --target sdfgen_python` (or `scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -- "
        "sdfgen_python`), or install the package with `pip install --no-build-isolation .`", name="sdfgen._sdfgen") from None
from ._sdfgen import *  # noqa: F401,F403 (every public name of the compiled module)
from ._sdfgen import __version__  # noqa: F401


def _argument_error(name, message):
    """pybind11's TypeError for arguments that match no signature (a listing of every overload over
    several lines) as one line: what was given and what the call takes."""
    lines = [line.strip() for line in message.splitlines()]
    takes = [_re.sub(r"\) -> .*$", ")", _re.sub(r"^\d+\.\s*", "", line)) for line in lines if _re.match(r"^\d+\.\s", line)]
    at = message.find("Invoked with:")  # the arguments' reprs (an array's span lines) up to the end
    given = message[at + len("Invoked with:"):] if at >= 0 else ""
    given = " ".join(given.split())
    if len(given) > 200:
        given = given[:200] + "..."
    message = "%s: the arguments (%s) do not match %s" % (name, given, " or ".join(takes) or "its signature")
    return message.replace(_sdfgen.__name__ + ".", __name__ + ".")


def _one_line_argument_errors(function, name):
    @_functools.wraps(function)
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except TypeError as error:
            message = str(error)
            if "incompatible function arguments" not in message and "incompatible constructor arguments" not in message:
                raise
            raise TypeError(_argument_error(name, message)) from None
    return call


def _wrap_module():
    builtin = type(_sdfgen.bake)
    for name in dir(_sdfgen):
        value = getattr(_sdfgen, name)
        if isinstance(value, builtin):
            globals()[name] = _one_line_argument_errors(value, "sdfgen.%s()" % name)
        elif isinstance(value, type) and value.__module__ == _sdfgen.__name__:
            # The classes as users name them (the compiled module is an implementation detail).
            value.__module__ = __name__
            for attribute, member in list(vars(value).items()):
                if attribute.startswith("__") and attribute != "__init__":
                    continue
                qualified = "sdfgen.%s()" % name if attribute == "__init__" else "sdfgen.%s.%s()" % (name, attribute)
                if isinstance(member, staticmethod):
                    setattr(value, attribute, staticmethod(_one_line_argument_errors(member.__func__, qualified)))
                elif type(member).__name__ == "instancemethod" or isinstance(member, builtin):
                    setattr(value, attribute, _one_line_argument_errors(getattr(value, attribute), qualified))


_wrap_module()
del _wrap_module, _glob, _os
