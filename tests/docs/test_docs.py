"""Every shell and Python code block of README.md and docs/*.md runs as written (ctest `docs`).

Blocks fenced ```sh, ```bash or ```python are extracted and run in order, file by file, each file
in its own scratch copy of the repository: a temporary folder holding links to every top-level
entry of the source tree, `build` linked to the already-built tree under test (SDFGEN_BUILD_DIR)
and `../shared` linked to the shared folder beside the source tree when there is one. So
`build/sdfgen ...` runs the tree's binary and `PYTHONPATH=build/python` finds its module, and what
a block writes (bunny.npz, out/) lands in the scratch folder, never in the source tree.
Shell blocks run with `bash -euo pipefail`; Python blocks with Debian's /usr/bin/python3 and
PYTHONPATH=build/python. Blocks that build the project use the already-built tree: the scratch
copy's `scripts/build.sh` (which ./run.sh calls) is a stand-in that runs `cmake --build` on the
tree under test for the targets asked (a no-op when it is up to date; configure options are the
tree's own), and a block that configures or builds by hand says so with a `small` marker below.

Markers, HTML comments on the lines just above a block (invisible on GitHub):
  <!-- doc-test: skip (why) -->                 not run; the reason is shown as pytest's skip reason
  <!-- doc-test: small (why) | OLD => NEW ... --> run with each OLD replaced by NEW (each OLD must be
                                                  in the block): a smaller size, or the built tree
  <!-- doc-test: setup COMMAND -->               a shell command run first (e.g. the bake that makes
                                                  the file a snippet reads)
Fenced blocks of other languages (cpp, cmake, json, text, plain) are not run."""
import os
import re
import shutil
import signal
import subprocess
import sys

import pytest

ROOT = os.path.abspath(os.environ.get("SDFGEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..")))
BUILD = os.path.abspath(os.environ.get("SDFGEN_BUILD_DIR", os.path.join(ROOT, "build")))
SHELLS = {"sh", "bash", "shell"}
RUN = SHELLS | {"python"}
TIMEOUT = 300


def doc_files():
    docs = os.path.join(ROOT, "docs")
    return ["README.md"] + sorted(os.path.join("docs", name) for name in os.listdir(docs) if name.endswith(".md"))


def blocks_of(path):
    """(line, language, code, markers) of each fenced block; markers: the doc-test comments just above."""
    lines = open(os.path.join(ROOT, path), encoding="utf-8").read().split("\n")
    found, i = [], 0
    while i < len(lines):
        fence = re.match(r"^(\s*)```(\S*)\s*$", lines[i])
        if not fence:
            i += 1
            continue
        indent, language, start = fence.group(1), fence.group(2), i
        i += 1
        body = []
        while not re.match(r"^\s*```\s*$", lines[i]):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        markers, j = [], start - 1
        while j >= 0 and lines[j].strip().startswith("<!--"):
            comment = re.match(r"^\s*<!--\s*doc-test:\s*(.*?)\s*-->\s*$", lines[j])
            if comment:
                markers.insert(0, comment.group(1))
            j -= 1
        found.append((start + 1, language, "\n".join(body) + "\n", markers))
        i += 1
    return found


CASES = [(path, line, language, code, markers) for path in doc_files() for line, language, code, markers in blocks_of(path)
         if language in RUN]


def scratch_repository(folder):
    """A scratch copy of the repository in folder/repo (links), with build/ the tree under test."""
    repo = os.path.join(folder, "repo")
    os.makedirs(repo)
    for name in os.listdir(ROOT):
        if name in (".git", "scripts") or name.startswith("build") or name == "out":
            continue
        os.symlink(os.path.join(ROOT, name), os.path.join(repo, name))
    os.symlink(BUILD, os.path.join(repo, "build"))
    os.makedirs(os.path.join(repo, "scripts"))
    for name in os.listdir(os.path.join(ROOT, "scripts")):
        if name != "build.sh":
            os.symlink(os.path.join(ROOT, "scripts", name), os.path.join(repo, "scripts", name))
    with open(os.path.join(repo, "scripts", "build.sh"), "w") as f:
        f.write("#!/usr/bin/env bash\n"
                "# The doc test's stand-in for scripts/build.sh: builds the asked targets in the tree under test.\n"
                "set -euo pipefail\n"
                "shift\n"
                "while [ $# -gt 0 ] && [ \"$1\" != -- ]; do shift; done\n"
                "[ $# -gt 0 ] && shift\n"
                f"cmake --build {BUILD} ${{1:+--target}} \"$@\"\n")
    os.chmod(os.path.join(repo, "scripts", "build.sh"), 0o755)
    shared = os.path.join(os.path.dirname(ROOT), "shared")
    if os.path.isdir(shared):
        os.symlink(shared, os.path.join(folder, "shared"))
    return repo


@pytest.fixture(scope="module")
def repositories(tmp_path_factory):
    made = {}

    def repository(path):
        if path not in made:
            made[path] = scratch_repository(str(tmp_path_factory.mktemp(os.path.basename(path).replace(".", "-"))))
        return made[path]
    return repository


def environment(repo):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(repo, "build", "python")
    env["MPLBACKEND"] = "Agg"
    for name in ("DISPLAY", "WAYLAND_DISPLAY"):
        env.pop(name, None)  # headless: run.sh renders PNGs instead of opening the viewer
    return env


def run(command, repo, what):
    """Runs a block in its own process group, killed whole (every child it started) on a timeout."""
    process = subprocess.Popen(command, cwd=repo, env=environment(repo), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True, start_new_session=True)
    try:
        output, _ = process.communicate(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        output, _ = process.communicate()
        pytest.fail(f"{what} ran past {TIMEOUT} s:\n{output[-6000:]}")
    finally:
        try:
            os.killpg(process.pid, signal.SIGKILL)  # whatever the block left running in the background
        except ProcessLookupError:
            pass
    assert process.returncode == 0, f"{what} failed with exit {process.returncode}:\n{output[-6000:]}"


@pytest.mark.parametrize("path, line, language, code, markers", CASES, ids=[f"{c[0]}:{c[1]}" for c in CASES])
def test_block_runs_as_written(repositories, path, line, language, code, markers):
    for marker in markers:
        if marker.startswith("skip"):
            reason = marker[len("skip"):].strip()
            assert reason.startswith("(") and reason.endswith(")") and len(reason) > 10, f"{path}:{line}: a skip needs a reason"
            pytest.skip(f"{path}:{line}: {reason[1:-1]}")
    repo = repositories(path)
    for marker in markers:
        if marker.startswith("small"):
            reason, *edits = [part.strip() for part in marker[len("small"):].split(" | ")]
            assert reason.startswith("(") and reason.endswith(")") and edits, f"{path}:{line}: a small marker needs a reason and edits"
            for edit in edits:
                old, new = edit.split(" => ")
                assert old in code, f"{path}:{line}: the marker's {old!r} is not in the block"
                code = code.replace(old, new)
        elif marker.startswith("setup "):
            run(["bash", "-euo", "pipefail", "-c", marker[len("setup "):]], repo, f"{path}:{line}: setup")
        else:
            assert marker.startswith("skip"), f"{path}:{line}: unknown doc-test marker {marker!r}"
    if language in SHELLS:
        run(["bash", "-euo", "pipefail", "-c", code], repo, f"{path}:{line}")
    else:
        run(["/usr/bin/python3", "-c", code], repo, f"{path}:{line}")


def test_blocks_were_found():
    assert len(CASES) > 20
    assert shutil.which("bash")
    assert sys.version_info >= (3, 8)
