-- premake5.lua: the sdfgen build for premake5 (gmake2 on Linux with GCC or Clang).
--
-- It builds what CMakeLists.txt builds, target for target: the same projects, sources, compile
-- definitions, include directories, flags and libraries (tests/premake/test_premake.py runs the
-- real premake5 and compares its compile and link commands with CMake's, under ctest `premake`).
-- Library names and paths are those of the Debian packages in extern/debian-packages.txt.
-- Platforms: Linux only. The code uses POSIX (mkstemp, fsync, sysconf, signals), /proc/self/exe
-- and GCC/Clang vector extensions, so Visual Studio and Xcode projects generated from this file
-- do not build; generating for another target OS (--os=windows or macosx) stops with an error.
--
--   premake5 gmake2 && make -C build-premake/gmake config=release -j2 sdfgen
--   build-premake/bin/Release/sdfgen render assets/bunny.obj -o bunny.png
--
-- Options mirror CMake's: --native (SDFGEN_NATIVE), --sanitize (SDFGEN_SANITIZE), --no-tests
-- (SDFGEN_BUILD_TESTS=OFF), --no-viewer (SDFGEN_VIEWER=OFF), --no-python (SDFGEN_PYTHON=OFF),
-- --no-openvdb (SDFGEN_OPENVDB=OFF), --no-assimp (SDFGEN_ASSIMP=OFF);
-- --build-dir=DIR puts the generated makefiles and all build output in DIR instead of
-- build-premake/ (ignored by git). CMake's "built on request" programs (bench/) are ordinary
-- projects here: `make` builds them too, `make sdfgen` only what sdfgen needs.

if os.target and os.target() ~= "linux" then
   error("sdfgen builds on Linux only (POSIX calls, /proc/self/exe, GCC/Clang vector extensions); target was " .. os.target())
end

newoption { trigger = "native", description = "Compile sdfgen's own code with -march=native: binaries for CPUs like this one only (CMake: -DSDFGEN_NATIVE=ON)" }
newoption { trigger = "sanitize", description = "Build with AddressSanitizer and UndefinedBehaviorSanitizer (CMake: -DSDFGEN_SANITIZE=ON)" }
newoption { trigger = "no-tests", description = "Leave out the GoogleTest programs (CMake: -DSDFGEN_BUILD_TESTS=OFF)" }
newoption { trigger = "no-viewer", description = "Build the core and the command line only, without OpenGL, GLFW, ImGui, OSMesa or glad (CMake: -DSDFGEN_VIEWER=OFF)" }
newoption { trigger = "no-python", description = "Leave out the Python module (CMake: -DSDFGEN_PYTHON=OFF)" }
newoption { trigger = "no-openvdb", description = "Leave out the OpenVDB plug-in: no .vdb files, no sdfgen surface (CMake: -DSDFGEN_OPENVDB=OFF)" }
newoption { trigger = "no-assimp", description = "Leave out the Assimp plug-in: OBJ meshes only (CMake: -DSDFGEN_ASSIMP=OFF)" }
newoption { trigger = "build-dir", value = "DIR", description = "Where the generated files and all build output go (default: build-premake/ in the source folder)" }

-- premake's gcc strips every binary built without debug symbols (-s); CMake's Release keeps the
-- symbol table (profilers and backtraces name the functions), and so does this build.
premake.tools.gcc.ldflags.symbols.Default = nil

SDFGEN_ROOT = _MAIN_SCRIPT_DIR or os.getcwd()
SDFGEN_BUILD_DIR = _OPTIONS["build-dir"] and path.getabsolute(_OPTIONS["build-dir"]) or (SDFGEN_ROOT .. "/build-premake")
SDFGEN_OBJ_DIR = SDFGEN_BUILD_DIR .. "/obj"
SDFGEN_VIEWER = not _OPTIONS["no-viewer"]
SDFGEN_OPENVDB = not _OPTIONS["no-openvdb"]
SDFGEN_ASSIMP = not _OPTIONS["no-assimp"]
-- Which plug-ins this build has, for the core (its "built without" errors) and the unit tests.
SDFGEN_PLUGIN_DEFINES = { "SDFGEN_HAS_OPENVDB=" .. (SDFGEN_OPENVDB and "1" or "0"), "SDFGEN_HAS_ASSIMP=" .. (SDFGEN_ASSIMP and "1" or "0") }
SDFGEN_SOURCE_DIR_DEFINE = 'SDFGEN_SOURCE_DIR="' .. SDFGEN_ROOT .. '"'

-- Usage requirements. CMake hands a target's PUBLIC/INTERFACE include directories, definitions
-- and libraries on to whatever links it; premake does not, so each function below adds what
-- linking one CMake target brings, and every project calls the ones for what it links.

-- CMake's sdfgen_flags: sdfgen's own code (not the extern/ glue). -Wno-psabi: the eight-lane
-- vector types are passed by value only between sdfgen's inline functions. -ffp-contract=off: no
-- fused multiply-adds anywhere (CMakeLists.txt says why).
function sdfgen_flags()
   warnings "Extra"   -- -Wall -Wextra
   buildoptions { "-Wno-psabi", "-ffp-contract=off" }
   if _OPTIONS["native"] then
      buildoptions { "-march=native" }
   end
   if _OPTIONS["sanitize"] then
      buildoptions { "-fsanitize=address,undefined", "-fno-omit-frame-pointer", "-fno-sanitize-recover=all" }
      linkoptions { "-fsanitize=address,undefined" }
   end
end

-- CMake's sdfgen::tbb (TBB::tbb): the library, and in Debug builds TBB's own checks.
function sdfgen_use_tbb()
   links { "tbb" }
   filter "configurations:Debug"
      defines { "TBB_USE_DEBUG" }
   filter {}
end

-- The core library (libsdfgen.so) as this build's own programs use it (CMake:
-- sdfgen_core_internal): the public and internal headers, sdfgen's flags, TBB.
function sdfgen_use_core()
   includedirs { SDFGEN_ROOT .. "/include", SDFGEN_ROOT .. "/src" }
   links { "sdfgen_core" }
   sdfgen_use_tbb()
   sdfgen_flags()
end

-- The OpenVDB and Assimp parts, opened by the core on first use from beside libsdfgen.so: a
-- program that may need them has them built first (CMake: add_dependencies).
function sdfgen_needs_plugins()
   if SDFGEN_OPENVDB then dependson { "sdfgen_openvdb" } end
   if SDFGEN_ASSIMP then dependson { "sdfgen_assimp" } end
end

-- CMake's sdfgen::openvdb (OpenVDB::openvdb): Imath's headers, OpenVDB's definitions, and the
-- libraries its package links (Boost iostreams, Imath, TBB, libm).
function sdfgen_use_openvdb()
   externalincludedirs { "/usr/include/Imath" }
   defines { "OPENVDB_ABI_VERSION_NUMBER=10", "OPENVDB_USE_DELAYED_LOADING", "BOOST_ALL_NO_LIB", "BOOST_IOSTREAMS_DYN_LINK" }
   links { "openvdb" }
   sdfgen_use_tbb()
   links { "boost_iostreams", "Imath-3_1", "m" }
end

-- GoogleTest (CMake: GTest::gtest_main, from Debian's static libgtest.a and libgtest_main.a).
function sdfgen_use_gtest()
   defines { "GTEST_HAS_PTHREAD=1" }
   links { "gtest_main", "gtest" }
end

-- Shared libraries, static libraries and modules are position-independent and programs
-- position-independent executables (CMake: CMAKE_POSITION_INDEPENDENT_CODE). Premake gives
-- programs an RPATH to the shared libraries they link, as CMake does in its build folder.
function sdfgen_program()
   kind "ConsoleApp"
   pic "Off"
   buildoptions { "-fPIE" }
end

workspace "sdfgen"
   location (SDFGEN_BUILD_DIR .. "/" .. (_ACTION or ""))
   configurations { "Release", "Debug" }   -- Release first: the default, as in CMakeLists.txt
   startproject "sdfgen"
   language "C++"
   cppdialect "C++17"
   pic "On"
   targetdir (SDFGEN_BUILD_DIR .. "/bin/%{cfg.buildcfg}")
   objdir (SDFGEN_OBJ_DIR .. "/%{cfg.buildcfg}/%{prj.name}")

   filter "configurations:Release"
      optimize "Speed"   -- -O3
      defines { "NDEBUG" }
   filter "configurations:Debug"
      symbols "On"
   filter {}

   include "extern"

-- Core library, libsdfgen.so: mesh, trees, distance and sign methods, field formats, point
-- queries. No OpenGL here. TBB, tinyobjloader and libzip stay private to it.
project "sdfgen_core"
   kind "SharedLib"
   targetname "sdfgen"
   files { "src/core/**.cpp" }
   includedirs { "include", "src" }
   defines(SDFGEN_PLUGIN_DEFINES)
   links { "dl" }
   sdfgen_use_tbb()
   links { "tinyobjloader", "zip" }
   sdfgen_flags()
   -- The kernels' functions start on cache lines, so that their speed does not shift with every
   -- change to the code linked before them.
   filter "files:src/core/distance/exact_avx2.cpp or src/core/distance/exact_baseline.cpp or src/core/accel/ray_avx2.cpp or src/core/accel/ray_baseline.cpp or src/core/accel/wide_avx2.cpp or src/core/accel/wide_baseline.cpp or src/core/sign/fan_avx512.cpp or src/core/sign/fan_avx2.cpp or src/core/sign/fan_baseline.cpp or src/core/sign/row_count_avx2.cpp or src/core/sign/row_count_baseline.cpp"
      buildoptions { "-falign-functions=64" }
   filter {}

-- OpenVDB (.vdb files, iso-surfaces) and Assimp (mesh formats other than OBJ) in libraries of
-- their own beside libsdfgen.so, which opens them on first use (src/core/runtime/plugin.hpp).
-- Each is optional (--no-openvdb, --no-assimp).
if SDFGEN_OPENVDB then
   project "sdfgen_openvdb"
      kind "SharedLib"
      files { "src/vdb/vdb.cpp" }
      sdfgen_use_core()
      sdfgen_use_openvdb()
end

if SDFGEN_ASSIMP then
   project "sdfgen_assimp"
      kind "SharedLib"
      files { "src/assimp/assimp_mesh.cpp", "src/assimp/gltf_guard.cpp" }
      sdfgen_use_core()
      -- assimp and what Assimp's CMake package links with it.
      links { "assimp", "z", "draco", "minizip", "rt" }
end

if SDFGEN_VIEWER then
   -- What linking sdfgen_render brings (CMake: its PUBLIC sdfgen::glad, and the private EGL,
   -- OSMesa (dl: libOSMesa is opened at run time) and stb libraries a static library passes on).
   function sdfgen_use_render()
      links { "sdfgen_render" }
      sdfgen_use_core()
      sdfgen_use_glad()
      links { "EGL", "dl", "stb" }
   end

   -- Renderers (OpenGL 4.5 through glad) and the headless contexts (EGL, then OSMesa). Shaders
   -- are read at run time from shaders/, beside the binary or in this source tree.
   project "sdfgen_render"
      kind "StaticLib"
      files { "src/render/*.cpp" }
      defines { SDFGEN_SOURCE_DIR_DEFINE }
      sdfgen_use_core()
      sdfgen_use_glad()

   -- The GPU compute device: OpenGL 4.5 compute shaders (shaders/*.comp) in a headless context,
   -- registered with the core at run time (include/sdfgen/device.hpp).
   project "sdfgen_gpu"
      kind "StaticLib"
      files { "src/gpu/*.cpp" }
      sdfgen_use_render()

   -- The viewer: GLFW window context, Dear ImGui panel, background generation.
   project "sdfgen_app"
      kind "StaticLib"
      files { "src/app/*.cpp" }
      sdfgen_use_render()
      sdfgen_use_imgui()
end

-- The command line. Without the viewer it lacks `view` and `render`.
project "sdfgen"
   sdfgen_program()
   files { "src/cli/*.cpp" }
   defines { SDFGEN_SOURCE_DIR_DEFINE, "SDFGEN_HAS_VIEWER=" .. (SDFGEN_VIEWER and "1" or "0") }
   sdfgen_needs_plugins()
   if SDFGEN_VIEWER then
      links { "sdfgen_gpu", "sdfgen_app" }
      sdfgen_use_render()
      sdfgen_link_imgui()
   else
      removefiles { "src/cli/render.cpp" }
      sdfgen_use_core()
   end

-- Benchmark programs (bench/CMakeLists.txt).
group "bench"
   -- The field formats' save/load benchmark: the installed library's interface only.
   project "bench_formats"
      sdfgen_program()
      files { "bench/formats.cpp" }
      includedirs { "include" }
      links { "sdfgen_core" }

   -- The ray method's error table against a sphere (its shape from the tests' support code).
   project "bench_ray_error"
      sdfgen_program()
      files { "bench/ray_error.cpp", "tests/support/shapes.cpp" }
      includedirs { "tests" }
      defines { SDFGEN_SOURCE_DIR_DEFINE }
      sdfgen_use_core()

   -- The exact kernel, the binary tree's build, the winding sign and point queries, each alone.
   for _, name in ipairs({ "kernel", "tree", "sign", "query" }) do
      project ("bench_" .. name)
         sdfgen_program()
         files { "bench/" .. name .. ".cpp" }
         sdfgen_use_core()
   end

   -- Peer drivers (bench/peers.sh): OpenVDB in builds with it, Embree 3 when libembree-dev is installed.
   if SDFGEN_OPENVDB then
      project "peer_openvdb"
         sdfgen_program()
         files { "bench/openvdb_sdf.cpp" }
         includedirs { "bench" }
         sdfgen_use_core()
         sdfgen_use_openvdb()
   end
   if os.findlib("embree3") then
      project "peer_embree"
         sdfgen_program()
         files { "bench/embree_sdf.cpp" }
         includedirs { "bench" }
         sdfgen_use_core()
         links { "embree3" }
   end
group ""

-- The Python package `sdfgen` (pybind11 + numpy) for Debian's /usr/bin/python3: the compiled
-- sdfgen._sdfgen with the package's Python files beside it in bin/CONFIG/python/sdfgen/
-- (PYTHONPATH=bin/CONFIG/python). The interpreter names its header folder and the module's file
-- suffix (_sdfgen.cpython-311-x86_64-linux-gnu.so); not with the sanitizers, whose runtime the
-- interpreter would need preloaded.
local python = "/usr/bin/python3"
if not _OPTIONS["no-python"] and not _OPTIONS["sanitize"] and os.isfile(python) then
   local function python_value(expression)
      local out, code = os.outputof(python .. ' -c "import sysconfig; print(' .. expression .. ')"')
      return code == 0 and out or nil
   end
   local include_dir = python_value("sysconfig.get_paths()['include']")
   local suffix = python_value("sysconfig.get_config_var('EXT_SUFFIX')")
   if not include_dir or not suffix or not os.isfile("/usr/include/pybind11/pybind11.h") then
      error("the Python module needs Debian's python3-dev and pybind11-dev (or premake5 --no-python)")
   end
   project "sdfgen_python"
      kind "SharedLib"
      targetdir (SDFGEN_BUILD_DIR .. "/bin/%{cfg.buildcfg}/python/sdfgen")
      targetname "_sdfgen"
      targetprefix ""
      targetextension (suffix)
      visibility "Hidden"
      inlinesvisibility "Hidden"
      files { "python/module.cpp", "python/nearest.cpp" }
      postbuildcommands { "{COPYFILE} " .. SDFGEN_ROOT .. "/python/sdfgen/*.py %{cfg.targetdir}" }
      externalincludedirs { include_dir }
      sdfgen_needs_plugins()
      if SDFGEN_VIEWER then
         -- bake(..., device="gpu"): the GPU compute device, in builds with the renderer it runs on.
         defines { "SDFGEN_PYTHON_GPU=1" }
         links { "sdfgen_gpu" }
         sdfgen_use_render()
      else
         sdfgen_use_core()
      end
end

if not _OPTIONS["no-tests"] then
   -- A GoogleTest program (tests/CMakeLists.txt): its sources, the tests' headers, run from anywhere.
   function sdfgen_gtest_program(sources)
      sdfgen_program()
      files(sources)
      includedirs { "tests" }
      defines { SDFGEN_SOURCE_DIR_DEFINE }
   end

   project "sdfgen_tests"
      -- Batch planning is the batch command's own code (src/cli/), tested here without the CLI.
      sdfgen_gtest_program({ "tests/*.cpp", "tests/support/*.cpp", "src/cli/batch_plan.cpp" })
      sdfgen_needs_plugins()
      sdfgen_use_gtest()
      sdfgen_use_core()
      defines(SDFGEN_PLUGIN_DEFINES)
      if SDFGEN_OPENVDB then
         sdfgen_use_openvdb()   -- the format tests read VDB files themselves
      end
      if SDFGEN_ASSIMP then
         files { "src/assimp/gltf_guard.cpp" }   -- the glTF guard (the Assimp plug-in's code), tested on its own too
      end
      links { "zip" }   -- the field reader tests write hostile .npz archives themselves
      links { "gmpxx", "gmp" }   -- GMP's rationals, the exact reference of the predicate tests

   if SDFGEN_VIEWER then
      project "sdfgen_render_tests"
         sdfgen_gtest_program({ "tests/render/test_render.cpp", "tests/support/shapes.cpp" })
         sdfgen_use_gtest()
         sdfgen_use_render()

      project "sdfgen_gpu_tests"
         sdfgen_gtest_program({ "tests/gpu/test_gpu.cpp", "tests/support/shapes.cpp", "tests/support/stand_in_device.cpp" })
         links { "sdfgen_gpu" }
         sdfgen_use_gtest()
         sdfgen_use_render()
   end
end
