#!/usr/bin/python3
"""premake5.lua builds what CMake builds: runs the real premake5 and compares, target by target,
its compile and link commands with the CMake build's.

    test_premake.py SOURCE_DIR CMAKE_BUILD_DIR CONFIG [PREMAKE_OPTION ...]

premake5 is the one in ../shared/tools/ beside the source folder, else one on PATH; without either
(Debian packages only premake4) the test is skipped with exit 77. `premake5 gmake2` writes its
makefiles into a temporary folder; `make -n -B` there prints every command the premake build would
run. CMake's side is the build folder's compile_commands.json (compiles) and build.ninja (links).
For each CMake target (all of them, the ones built only on request included), premake must have a
project of the same name that compiles the same sources, each with the same definitions, include
directories (-I and -isystem) and compile flags, links the same libraries, and produces a
file of the same kind and name. CONFIG is the CMake build type (Release or Debug); the options
are premake5.lua's counterparts of the CMake options the build folder was configured with.
Prints each difference and exits 1 on any; prints one summary line on success.
"""
import collections
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

if len(sys.argv) < 4:
    sys.exit(__doc__)
source_dir = os.path.realpath(sys.argv[1])
cmake_build = os.path.realpath(sys.argv[2])
config = sys.argv[3]
premake_options = sys.argv[4:]

premake = os.path.join(os.path.dirname(source_dir), "shared", "tools", "premake5")
if not os.access(premake, os.X_OK):
    premake = shutil.which("premake5")
if not premake:
    print("premake test skipped: no premake5 (not in ../shared/tools/ beside the source folder, "
          "nor on PATH; Debian packages only premake4)")
    sys.exit(77)
for needed in ("compile_commands.json", "build.ninja"):
    if not os.path.isfile(os.path.join(cmake_build, needed)):
        sys.exit(f"premake test: {cmake_build}/{needed} is missing (a Ninja build folder is needed)")


def glad_path(path):
    """The generated glad loader lives in each build's own folder: one name for both."""
    return re.sub(r"^.*/glad/(include|src)", r"<glad>/\1", path)


def norm(path, cwd):
    return glad_path(os.path.normpath(os.path.join(cwd, path)))


def library_name(token):
    """-lNAME, or a library file's path, as NAME (libsdfgen.so.0.1.0 -> sdfgen)."""
    if token.startswith("-l"):
        return token[2:]
    base = os.path.basename(token)
    match = re.fullmatch(r"lib(.+?)\.(a|so)(\.[0-9a-z.]+)?", base)
    return match.group(1) if match else None


def compile_settings(args, cwd):
    """(source, definitions, include directories, flags) of one compiler command line."""
    defines, includes, flags = set(), set(), set()
    source = None
    i = 1
    while i < len(args):
        a = args[i]
        if a in ("-o", "-MF", "-MT", "-MQ"):
            i += 2
            continue
        if a in ("-I", "-isystem"):
            includes.add((a, norm(args[i + 1], cwd)))
            i += 2
            continue
        if a.startswith("-isystem"):
            includes.add(("-isystem", norm(a[len("-isystem"):], cwd)))
        elif a.startswith("-I"):
            includes.add(("-I", norm(a[2:], cwd)))
        elif a.startswith("-D"):
            if not a.endswith("_EXPORTS"):   # CMake's own mark of a shared library's sources
                defines.add(a)
        elif a in ("-c", "-MD", "-MP", "-MMD"):
            pass
        elif a.startswith("-"):
            flags.add(a)
        else:
            source = norm(a, cwd)
        i += 1
    return source, frozenset(defines), frozenset(includes), frozenset(flags)


Target = collections.namedtuple("Target", "sources libraries output link_flags")
LINK_FLAGS = re.compile(r"^(-s|-rdynamic|-pthread|-static.*|-fsanitize=.*|-flto.*)$")


def new_target():
    return Target({}, [], [None], set())


# CMake: compile_commands.json, each object file under CMakeFiles/TARGET.dir/.
cmake = collections.defaultdict(new_target)
with open(os.path.join(cmake_build, "compile_commands.json")) as f:
    for entry in json.load(f):
        args = entry["arguments"] if "arguments" in entry else shlex.split(entry["command"])
        output = args[args.index("-o") + 1]
        target = re.search(r"CMakeFiles/([^/]+)\.dir/", output).group(1)
        settings = compile_settings(args, entry["directory"])
        cmake[target].sources[settings[0]] = settings[1:]

# CMake: build.ninja's link statements, "build OUTPUT: KIND_LINKER__TARGET_CONFIG ...", then
# indented variables, LINK_LIBRARIES and LINK_FLAGS among them.
with open(os.path.join(cmake_build, "build.ninja")) as f:
    ninja = f.read()
link_rule = re.compile(r"^build ([^:|]+?)(?: [^:]*)?: (C|CXX)_(EXECUTABLE|SHARED_LIBRARY|MODULE_LIBRARY|STATIC_LIBRARY)_LINKER__(\S+)_" + re.escape(config) + r" ")
for block in ninja.split("\n\n"):
    lines = block.strip("\n").split("\n")
    match = next((link_rule.match(line) for line in lines if link_rule.match(line)), None)
    if not match:
        continue
    target = match.group(4)
    if target not in cmake:
        continue
    cmake[target].output[0] = (match.group(3), os.path.basename(match.group(1)))
    for line in lines:
        name, _, value = line.strip().partition(" = ")
        if name == "LINK_LIBRARIES":
            cmake[target].libraries.extend(n for n in map(library_name, shlex.split(value)) if n)
        elif name in ("LINK_FLAGS", "FLAGS") and match.group(3) != "STATIC_LIBRARY":
            cmake[target].link_flags.update(t for t in shlex.split(value) if LINK_FLAGS.match(t))

# premake: generate into a temporary folder, then `make -n -B` prints every command. LDDEPS= keeps
# make from looking for the libraries that a dry run does not build.
with tempfile.TemporaryDirectory(prefix="sdfgen-premake-") as tmp:
    generate = subprocess.run([premake, "--file=" + os.path.join(source_dir, "premake5.lua"), "--build-dir=" + tmp]
                              + premake_options + ["gmake2"], capture_output=True, text=True)
    if generate.returncode != 0:
        sys.exit(f"premake test: premake5 gmake2 failed:\n{generate.stdout}{generate.stderr}")
    makefiles = [d for d in os.listdir(tmp) if os.path.isfile(os.path.join(tmp, d, "Makefile"))]
    if len(makefiles) != 1:
        sys.exit(f"premake test: expected one folder with a Makefile in {tmp}, found {makefiles}")
    make_dir = os.path.join(tmp, makefiles[0])
    dry = subprocess.run(["make", "-n", "-B", "config=" + config.lower(), "LDDEPS="], cwd=make_dir,
                         capture_output=True, text=True)
    if dry.returncode != 0:
        sys.exit(f"premake test: make -n failed:\n{dry.stdout[-3000:]}{dry.stderr}")
    premake_targets = collections.defaultdict(new_target)
    project = None
    for line in dry.stdout.splitlines():
        building = re.match(r'echo "==== Building (\S+) \(', line)
        if building:
            project = building.group(1)
            continue
        if not line.startswith(("gcc ", "g++ ", "clang ", "clang++ ", "cc ", "c++ ", "ar ")):
            continue
        args = shlex.split(line)
        target = premake_targets[project]
        if "-c" in args:
            settings = compile_settings(args, make_dir)
            target.sources[settings[0]] = settings[1:]
        elif args[0] == "ar":
            target.output[0] = ("STATIC_LIBRARY", os.path.basename(args[2]))
        else:
            output = os.path.basename(args[args.index("-o") + 1])
            kind = "SHARED_LIBRARY" if "-shared" in args else "EXECUTABLE"
            target.output[0] = (kind, output)
            inputs = (a for a in args[1:] if not a.endswith(".o") and a != args[args.index("-o") + 1])
            target.libraries.extend(n for n in map(library_name, inputs) if n)
            target.link_flags.update(a for a in args if LINK_FLAGS.match(a))

problems = []
for name in sorted(set(cmake) | set(premake_targets)):
    if name not in premake_targets:
        problems.append(f"{name}: a CMake target that premake5.lua does not build")
        continue
    if name not in cmake:
        problems.append(f"{name}: a premake project that CMake does not build")
        continue
    c, p = cmake[name], premake_targets[name]
    for source in sorted(set(c.sources) | set(p.sources)):
        if source not in p.sources:
            problems.append(f"{name}: {source} compiled by CMake only")
        elif source not in c.sources:
            problems.append(f"{name}: {source} compiled by premake only")
        else:
            for what, cs, ps in zip(("definitions", "include directories", "flags"), c.sources[source], p.sources[source]):
                if cs != ps:
                    detail = []
                    if cs - ps:
                        detail.append("CMake only: " + " ".join(sorted(map(str, cs - ps))))
                    if ps - cs:
                        detail.append("premake only: " + " ".join(sorted(map(str, ps - cs))))
                    problems.append(f"{name}: {os.path.relpath(source, source_dir)} {what} differ ({'; '.join(detail)})")
    # CMake names the core library libsdfgen.so.VERSION (with its SONAME links); a Python module's
    # kind is CMake's MODULE_LIBRARY, a shared library to the linker.
    c_kind, c_file = c.output[0] or (None, None)
    p_kind, p_file = p.output[0] or (None, None)
    c_kind = "SHARED_LIBRARY" if c_kind == "MODULE_LIBRARY" else c_kind
    c_file = re.sub(r"(\.so)\.[0-9.]+$", r"\1", c_file or "")
    if (c_kind, c_file) != (p_kind, p_file or ""):
        problems.append(f"{name}: CMake makes {c_kind} {c_file}, premake {p_kind} {p_file}")
    if set(c.libraries) != set(p.libraries):
        problems.append(f"{name}: libraries differ (CMake only: {sorted(set(c.libraries) - set(p.libraries))}; "
                        f"premake only: {sorted(set(p.libraries) - set(c.libraries))})")
    if c.link_flags != p.link_flags:
        problems.append(f"{name}: link flags differ (CMake: {sorted(c.link_flags)}; premake: {sorted(p.link_flags)})")

for problem in problems:
    print("premake test: " + problem)
if problems:
    sys.exit(1)
objects = sum(len(t.sources) for t in cmake.values())
print(f"premake test: {len(cmake)} targets, {objects} compiled sources: premake5.lua builds what CMake builds "
      f"(same sources, definitions, include directories, flags, libraries and outputs; {os.path.basename(premake)} "
      f"from {os.path.dirname(premake)})")
