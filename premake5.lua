-- premake5.lua: premake5 description of the sdfgen build, for gmake2 users on Linux with GCC or
-- Clang.
--
-- CMakeLists.txt is the real build; this file mirrors it (same projects, sources, flags and system
-- libraries) and tests/premake/check.lua keeps the two in step (ctest runs it). Library names and
-- paths are those of the Debian packages in extern/debian-packages.txt.
-- Platforms: Linux only. The code uses POSIX (mkstemp, fsync, sysconf, signals), /proc/self/exe
-- and GCC/Clang vector extensions, so Visual Studio and Xcode projects generated from this file
-- do not build; porting would need those replaced first. Generating for another target OS
-- (premake5 --os=windows or macosx, or running premake there) stops with an error.
--
--   premake5 gmake2 && make -C build-premake/gmake2 config=release -j2
--   premake5 --native gmake2
--
-- Generated projects and all build output go to build-premake/ (ignored by git).
--
-- The Python module (python/, pybind11) is built by CMake only: it needs CMake's FindPython to
-- match the interpreter's headers and extension suffix, which premake has no equivalent for.

if os.target and os.target() ~= "linux" then
   error("sdfgen builds on Linux only (POSIX calls, /proc/self/exe, GCC/Clang vector extensions); target was " .. os.target())
end

newoption {
   trigger = "native",
   description = "Compile everything with -march=native: binaries for CPUs like this one only (CMake: -DSDFGEN_NATIVE=ON)",
}
newoption {
   trigger = "sanitize",
   description = "Build with AddressSanitizer and UndefinedBehaviorSanitizer (CMake: -DSDFGEN_SANITIZE=ON)",
}
newoption {
   trigger = "no-tests",
   description = "Leave out the GoogleTest suite (CMake: -DSDFGEN_BUILD_TESTS=OFF)",
}

SDFGEN_ROOT = _MAIN_SCRIPT_DIR or os.getcwd()
SDFGEN_BUILD_DIR = SDFGEN_ROOT .. "/build-premake"
SDFGEN_OBJ_DIR = SDFGEN_BUILD_DIR .. "/obj"

-- System libraries a program linking sdfgen_core needs (CMake: sdfgen::tbb, and
-- tinyobjloader::tinyobjloader, which on Debian is a shared library, libtinyobjloader.so, not
-- header-only; glm is header-only; sdfgen::libzip; dl, as the OpenVDB and Assimp parts,
-- sdfgen_openvdb and sdfgen_assimp, are opened at run time). Premake does not pass a static
-- library's links on to the programs that use it, so every program that links sdfgen_core lists
-- these itself, through sdfgen_use_core().
SDFGEN_CORE_LINKS = { "tbb", "tinyobjloader", "zip", "dl" }
-- sdfgen::openvdb: OpenVDB::openvdb with the Boost iostreams and Imath libraries its headers need.
SDFGEN_OPENVDB_LINKS = { "openvdb", "boost_iostreams", "Imath-3_1", "tbb" }

-- What code including OpenVDB's headers needs (CMake: OpenVDB::openvdb's include directories and
-- compile definitions): sdfgen_openvdb (the .vdb format, iso-surfaces) and the tests that read VDBs.
function sdfgen_openvdb_headers()
   includedirs { "/usr/include/Imath" }
   defines { "OPENVDB_ABI_VERSION_NUMBER=10", "OPENVDB_USE_DELAYED_LOADING", "BOOST_ALL_NO_LIB", "BOOST_IOSTREAMS_DYN_LINK" }
end

-- The compile flags CMake's sdfgen_flags target gives sdfgen's own code (not the extern/ glue).
function sdfgen_flags()
   warnings "Extra"
   -- No fused multiply-adds anywhere (CMakeLists.txt says why): the kernel's AVX2 and baseline
   -- copies and the GPU's shaders round as this code does.
   buildoptions { "-Wno-psabi", "-ffp-contract=off" }
   if _OPTIONS["native"] then
      buildoptions { "-march=native" }
   end
   if _OPTIONS["sanitize"] then
      buildoptions { "-fsanitize=address,undefined", "-fno-omit-frame-pointer", "-fno-sanitize-recover=all" }
      linkoptions { "-fsanitize=address,undefined" }
   end
end

-- What linking sdfgen_core brings along (CMake: its PUBLIC include directory and link libraries).
-- The program exports the core's symbols (-rdynamic) for sdfgen_openvdb and sdfgen_assimp, which
-- the core opens beside the program on first use (src/core/plugin.hpp).
function sdfgen_use_core()
   includedirs { SDFGEN_ROOT .. "/include", SDFGEN_ROOT .. "/src" }
   links { "sdfgen_core" }
   links(SDFGEN_CORE_LINKS)
   linkoptions { "-rdynamic" }
   dependson { "sdfgen_openvdb", "sdfgen_assimp" }
end

workspace "sdfgen"
   location (SDFGEN_BUILD_DIR .. "/" .. (_ACTION or ""))
   configurations { "Release", "Debug" }   -- Release first: the default, as in CMakeLists.txt
   startproject "sdfgen"
   language "C++"
   cppdialect "C++17"
   targetdir (SDFGEN_BUILD_DIR .. "/bin/%{cfg.buildcfg}")
   objdir (SDFGEN_OBJ_DIR .. "/%{cfg.buildcfg}/%{prj.name}")

   filter "configurations:Release"
      optimize "Speed"   -- -O3
      defines { "NDEBUG" }
   filter "configurations:Debug"
      symbols "On"
   filter {}

   include "extern"

-- Core library: mesh, tree, generators, field I/O. No OpenGL here.
project "sdfgen_core"
   kind "StaticLib"
   files { "src/core/**.cpp", "src/core/**.hpp", "include/sdfgen/**.hpp" }
   includedirs { "include", "src" }
   sdfgen_flags()

-- OpenVDB (.vdb files, iso-surfaces), opened by the core on first use: its symbols from the core
-- are the program's (CMake: a shared library beside libsdfgen.so that links it).
project "sdfgen_openvdb"
   kind "SharedLib"
   files { "src/vdb/**.cpp" }
   includedirs { "include", "src" }
   sdfgen_openvdb_headers()
   links(SDFGEN_OPENVDB_LINKS)
   sdfgen_flags()

-- Assimp (mesh formats other than OBJ), opened by the core on first use, likewise.
project "sdfgen_assimp"
   kind "SharedLib"
   files { "src/assimp/**.cpp" }
   includedirs { "include", "src" }
   links { "assimp" }
   sdfgen_flags()

-- Renderers (OpenGL 4.5 through glad) and the headless contexts (EGL, else OSMesa). Shaders are read at run
-- time from shaders/, beside the binary or in this source tree (SDFGEN_SOURCE_DIR).
project "sdfgen_render"
   kind "StaticLib"
   files { "src/render/**.cpp", "src/render/**.hpp", "shaders/*" }
   includedirs { "include", "src", GLAD_DIR .. "/include" }
   defines { 'SDFGEN_SOURCE_DIR="' .. SDFGEN_ROOT .. '"' }
   sdfgen_flags()

-- System libraries a program linking sdfgen_render needs (CMake: sdfgen::egl, which is EGL,
-- sdfgen::osmesa, which is dl, as libOSMesa is opened at run time, and sdfgen::stb, Debian's
-- libstb.so with the stb_image and stb_image_write implementations).
SDFGEN_RENDER_LINKS = { "EGL", "dl", "stb" }

function sdfgen_use_render()
   links { "sdfgen_render" }
   links(SDFGEN_RENDER_LINKS)
   sdfgen_use_glad()
end

-- The GPU compute device: OpenGL 4.5 compute shaders (shaders/*.comp) in a headless context,
-- registered with the core at run time (include/sdfgen/device.hpp).
project "sdfgen_gpu"
   kind "StaticLib"
   files { "src/gpu/**.cpp", "src/gpu/**.hpp" }
   includedirs { "include", "src", GLAD_DIR .. "/include" }
   sdfgen_flags()

-- The viewer: GLFW window context, Dear ImGui panel, background generation.
project "sdfgen_app"
   kind "StaticLib"
   files { "src/app/**.cpp", "src/app/**.hpp" }
   includedirs { "include", "src", GLAD_DIR .. "/include", IMGUI_INCLUDE_DIR, IMGUI_INCLUDE_DIR .. "/backends" }
   sdfgen_flags()

-- Command line front end.
project "sdfgen"
   kind "ConsoleApp"
   files { "src/cli/**.cpp", "src/cli/**.hpp" }
   defines { 'SDFGEN_SOURCE_DIR="' .. SDFGEN_ROOT .. '"' }
   links { "sdfgen_app", "sdfgen_gpu" }
   sdfgen_use_imgui()
   sdfgen_use_render()
   sdfgen_use_core()
   sdfgen_flags()

if not _OPTIONS["no-tests"] then
   -- A GoogleTest program: its own sources plus the shared test support, run from the repo root.
   function sdfgen_gtest_program(sources)
      kind "ConsoleApp"
      files { sources, "tests/support/*.cpp", "tests/support/*.hpp" }
      includedirs { "tests" }
      defines { 'SDFGEN_SOURCE_DIR="' .. SDFGEN_ROOT .. '"', "GTEST_HAS_PTHREAD=1" }
   end

   -- Links gtest after the project's own libraries, then our warning and tuning flags.
   function sdfgen_use_gtest()
      links { "gtest_main", "gtest", "pthread" }
      sdfgen_flags()
   end
   -- GoogleTest suite (tests/CMakeLists.txt), from Debian's libgtest-dev: static libgtest.a and
   -- libgtest_main.a. CMake's GTest::gtest brings GTEST_HAS_PTHREAD=1 and Threads::Threads, which
   -- is pthread (empty on glibc 2.34 and later, where libpthread is part of libc).
   project "sdfgen_tests"
      sdfgen_gtest_program("tests/*.cpp")
      sdfgen_openvdb_headers()
      sdfgen_use_core()
      links(SDFGEN_OPENVDB_LINKS) -- the format tests read VDB files themselves
      links { "gmpxx", "gmp" } -- GMP's rationals, the exact reference of the predicate tests
      sdfgen_use_gtest()

   -- Render tests under OSMesa (tests/CMakeLists.txt: sdfgen_render_tests).
   project "sdfgen_render_tests"
      sdfgen_gtest_program("tests/render/*.cpp")
      sdfgen_use_render()
      sdfgen_use_core()
      sdfgen_use_gtest()

   -- The GPU device against the CPU (tests/CMakeLists.txt: sdfgen_gpu_tests).
   project "sdfgen_gpu_tests"
      sdfgen_gtest_program("tests/gpu/*.cpp")
      links { "sdfgen_gpu" }
      sdfgen_use_render()
      sdfgen_use_core()
      sdfgen_use_gtest()
end
