#!/usr/bin/env python3
"""Checks that #include lines run one way through the layers (docs/testing.md: the layering check).

Usage: scripts/check_layers.py [ROOT]   (ROOT: the source tree, by default this script's)

The core's folders (src/core/*) form layers, each of which may include only itself and those
below it:

    runtime, simd  <  mesh  <  accel  <  method  <  distance, sign  <  bake  <  io

Folders of one rank (runtime and simd; distance and sign) include neither each other. The public
headers (include/sdfgen/) are everyone's and include only each other. Above the core come the
plug-ins (src/vdb, src/assimp), then the front ends, in this order: src/render, src/gpu, src/app,
then src/cli and python/; the core includes none of them. The front ends (src/cli, src/app,
src/render, python/) reach the core through include/sdfgen/ alone: a front end's include of a core
internal is a violation too, unless that header is in EXPORTED (an interface the core exports on
purpose, which itself may include only the standard library and include/sdfgen/). The plug-ins
and the GPU device implement the core's internal plug-in interfaces and may include its internals.

Each violation is "FILE -> INCLUDED" (paths from ROOT). The ones that existed when this check was
added are listed in BASELINE, which may only shrink: the check fails on any violation not in it,
and on any entry of it that no longer occurs (remove the entry along with the include). Exit
status 0 when the tree holds exactly the baseline's violations, 1 otherwise.
"""
import os
import re
import sys

# The core's layers, lowest first; one rank may hold several folders (siblings).
CORE_RANKS = [("runtime", "simd"), ("mesh",), ("accel",), ("method",), ("distance", "sign"), ("bake",), ("io",)]
# Above the core, lowest first.
OUTER_RANKS = [("vdb", "assimp"), ("render",), ("gpu",), ("app",), ("cli", "python")]
FRONT_ENDS = {"cli", "app", "render", "python"}
# Core internals a front end may include: leaf headers that every part of sdfgen is meant to use
# alike, each including only the standard library and include/sdfgen/ (checked).
EXPORTED = {
    "src/core/io/atomic_file.hpp",     # every output file is written atomically, the front ends' own too (PNG, query .npy)
    "src/core/runtime/file_extension.hpp",  # the one way a file's format is read from its name
    "src/core/simd/path.hpp",          # which copy of the SIMD kernels runs: for `sdfgen info`, tests and benchmarks
    "src/core/runtime/parallel.hpp",   # the one way work is spread over RunControl's threads, with its progress and cancel
}

BASELINE: set = set()

SOURCE_EXTENSIONS = (".cpp", ".hpp", ".h", ".inc")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.MULTILINE)


def sources(root):
    """Every source file that the check reads, as paths from root."""
    for top in ("src", "include", "python"):
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs.sort()
            for name in sorted(files):
                if name.endswith(SOURCE_EXTENSIONS):
                    yield os.path.relpath(os.path.join(folder, name), root)


def resolve(root, path, included):
    """The included file as a path from root (beside the includer first, then src/ and include/,
    as the build's include directories), or None for a header from outside the tree."""
    for base in (os.path.dirname(path), "src", "include"):
        candidate = os.path.normpath(os.path.join(base, included))
        if os.path.isfile(os.path.join(root, candidate)):
            return candidate
    return None


def place(path):
    """(part, folder): part is 'public', 'core' or 'outer'; folder the layer's folder name."""
    parts = path.split(os.sep)
    if parts[0] == "include":
        return "public", "sdfgen"
    if parts[0] == "python":
        return "outer", "python"
    if parts[1] == "core":
        return "core", parts[2]
    return "outer", parts[1]


def rank(part, folder):
    ranks = CORE_RANKS if part == "core" else OUTER_RANKS
    for index, names in enumerate(ranks):
        if folder in names:
            return index
    raise SystemExit(f"check_layers.py: no layer for folder {folder!r}: add it to CORE_RANKS or OUTER_RANKS")


def violation(source, target):
    """Why `source` may not include `target`, or None."""
    (part, folder), (to_part, to_folder) = place(source), place(target)
    if to_part == "public" or (part, folder) == (to_part, to_folder):
        return None
    if part == "public":
        return "a public header includes an internal one"
    if part == "core" and to_part == "outer":
        return "the core includes a plug-in or front end"
    if part == to_part:
        here, there = rank(part, folder), rank(to_part, to_folder)
        if there > here:
            return "upward"
        if there == here:
            return "between sibling layers"
        return None
    # An outer folder includes the core.
    if folder in FRONT_ENDS and target not in EXPORTED:
        return "a front end includes a core internal"
    return None


def exported_leak(source, target):
    """Why an exported header may not include `target`, or None."""
    if source in EXPORTED and place(target)[0] != "public":
        return "an exported interface includes an internal one"
    return None


def violations(root):
    found = {}
    for path in sources(root):
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            text = f.read()
        for included in INCLUDE.findall(text):
            target = resolve(root, path, included)
            if target is None:
                continue
            why = exported_leak(path, target) or violation(path, target)
            if why:
                found[f"{path} -> {target}"] = why
    return found


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    found = violations(root)
    new = sorted(set(found) - BASELINE)
    gone = sorted(BASELINE - set(found))
    for entry in new:
        print(f"layers: {entry}: {found[entry]} (see the layers in scripts/check_layers.py)")
    for entry in gone:
        print(f"layers: {entry}: no longer there; remove it from BASELINE in scripts/check_layers.py")
    if new or gone:
        return 1
    print(f"layers: {len(found)} known violations, none new")
    return 0


if __name__ == "__main__":
    sys.exit(main())
