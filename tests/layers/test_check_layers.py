#!/usr/bin/env python3
"""scripts/check_layers.py catches what it is for: run on a copy of the sources with one include
added against the layers (or one baselined include removed), it fails and names the include.
Usage: test_check_layers.py SOURCE_DIR"""
import os
import shutil
import subprocess
import sys
import tempfile

source = sys.argv[1]
script = os.path.join(source, "scripts", "check_layers.py")
failures = []


def check(root):
    run = subprocess.run([sys.executable, script, root], capture_output=True, text=True)
    return run.returncode, run.stdout + run.stderr


def expect(what, root, code, text):
    got, output = check(root)
    if got != code or text not in output:
        failures.append(f"{what}: expected exit {code} and '{text}', got exit {got}:\n{output}")
    else:
        print(f"ok: {what}: {output.strip().splitlines()[0]}")


with tempfile.TemporaryDirectory(prefix="sdfgen-layers-") as scratch:
    def fresh():
        """A copy of the tree's sources, as the check reads them."""
        root = os.path.join(scratch, "tree")
        shutil.rmtree(root, ignore_errors=True)
        for top in ("src", "include", "python"):
            shutil.copytree(os.path.join(source, top), os.path.join(root, top),
                            ignore=shutil.ignore_patterns("__pycache__", "*.py", "*.txt"))
        return root

    def add_include(root, path, included):
        with open(os.path.join(root, path), "a") as f:
            f.write(f'\n#include "{included}"\n')

    expect("the tree as it is", fresh(), 0, "none new")

    root = fresh()
    add_include(root, "src/core/mesh/mesh.cpp", "core/bake/bake.hpp")
    expect("an upward include", root, 1, "src/core/mesh/mesh.cpp -> src/core/bake/bake.hpp: upward")

    root = fresh()
    add_include(root, "src/core/distance/exact.cpp", "core/sign/winding_sign.hpp")
    expect("an include between siblings", root, 1, "src/core/distance/exact.cpp -> src/core/sign/winding_sign.hpp: between sibling layers")

    root = fresh()
    add_include(root, "src/cli/main.cpp", "core/runtime/memory.hpp")
    expect("a front end's include of a core internal", root, 1,
           "src/cli/main.cpp -> src/core/runtime/memory.hpp: a front end includes a core internal")

    root = fresh()
    add_include(root, "src/core/bake/model.cpp", "app/viewer.hpp")
    expect("the core including a front end", root, 1, "src/core/bake/model.cpp -> src/app/viewer.hpp: the core includes a plug-in or front end")

    root = fresh()
    add_include(root, "include/sdfgen/mesh.hpp", "core/accel/bvh.hpp")
    expect("a public header including an internal one", root, 1,
           "include/sdfgen/mesh.hpp -> src/core/accel/bvh.hpp: a public header includes an internal one")

    root = fresh()
    add_include(root, "src/core/runtime/file_extension.hpp", "core/accel/bvh.hpp")
    expect("an exported interface including an internal one", root, 1,
           "src/core/runtime/file_extension.hpp -> src/core/accel/bvh.hpp: an exported interface includes an internal one")

    # A baselined include removed: the baseline must lose its entry too (while it has one).
    sys.path.insert(0, os.path.dirname(script))
    import check_layers
    if check_layers.BASELINE:
        entry = sorted(check_layers.BASELINE)[0]
        including, included = entry.split(" -> ")
        root = fresh()
        path = os.path.join(root, including)
        with open(path) as f:
            lines = [line for line in f if not (line.lstrip().startswith('#include "') and included.endswith(line.split('"')[1]))]
        with open(path, "w") as f:
            f.writelines(lines)
        expect("a baselined include gone", root, 1, entry + ": no longer there")
    else:
        print("ok: no baselined include to remove")

for failure in failures:
    print("FAIL", failure)
sys.exit(1 if failures else 0)
