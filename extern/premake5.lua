-- extern/premake5.lua: build glue for third-party libraries, the premake counterpart of
-- extern/CMakeLists.txt. Included from the top-level premake5.lua inside its workspace, which sets
-- SDFGEN_OBJ_DIR and SDFGEN_VIEWER. Everything comes from the Debian packages in
-- extern/debian-packages.txt; glm, CLI11 and stb's headers are in /usr/include and need nothing here.
--
-- Premake does not pass a static library's links or include directories on to the programs that
-- use it, so a program using glad or the ImGui backends calls sdfgen_use_glad() or
-- sdfgen_use_imgui(), which add what CMake's sdfgen::glad and sdfgen::imgui targets carry.

if not SDFGEN_VIEWER then
   return
end

-- glad: the GL 4.5 core loader, generated from the spec bundled with python3-glad into
-- <objdir>/glad, outside every project's own object directory so that a clean keeps it.
GLAD_DIR = SDFGEN_OBJ_DIR .. "/glad"
local glad_command = 'glad --quiet --api gl:core=4.5 --reproducible --out-path "' .. GLAD_DIR .. '" c'
local glad_source = GLAD_DIR .. "/src/gl.c"

-- gmake checks that gl.c exists before it runs any prebuild command, so a first build from a fresh
-- tree would stop at "No rule to make target"; generate the loader now if it is missing. The
-- prebuild command below covers a later deletion in IDEs, and skips the (slow, file-rewriting)
-- generation when gl.c is there, so that gl.c is not recompiled on every build.
if _ACTION and _ACTION ~= "clean" and not os.isfile(glad_source) then
   print("Generating the glad OpenGL 4.5 core loader in " .. GLAD_DIR)
   if not os.execute(glad_command) then
      premake.warn("could not run glad (Debian package python3-glad); the glad project will not build")
   end
end

project "sdfgen_glad"
   kind "StaticLib"
   language "C"
   files { glad_source }
   externalincludedirs { GLAD_DIR .. "/include" }
   prebuildcommands { 'test -f "' .. glad_source .. '" || ' .. glad_command }

function sdfgen_use_glad()
   externalincludedirs { GLAD_DIR .. "/include" }
   links { "sdfgen_glad", "dl" }
end

-- Dear ImGui: the library is Debian's libimgui (static, and built against Debian's libstb: pkg-config
-- imgui gives stb's include folder and library too); its GLFW and OpenGL3 backends ship only as
-- sources in the package's examples, so they are compiled here.
IMGUI_INCLUDE_DIRS = { "/usr/include/imgui", "/usr/include/imgui/backends", "/usr/include/stb" }
local imgui_backends = "/usr/share/doc/libimgui-dev/examples/backends"

project "sdfgen_imgui"
   kind "StaticLib"
   files { imgui_backends .. "/imgui_impl_glfw.cpp", imgui_backends .. "/imgui_impl_opengl3.cpp" }
   externalincludedirs(IMGUI_INCLUDE_DIRS)

-- The libraries linking sdfgen_imgui brings (CMake: PkgConfig::IMGUI, which is imgui and stb,
-- PkgConfig::GLFW3, OpenGL::GL, which is GLVND's OpenGL and GLX, and ${CMAKE_DL_LIBS}); a program
-- that links a static library using ImGui privately (sdfgen_app) needs these but not the headers.
function sdfgen_link_imgui()
   links { "sdfgen_imgui", "imgui", "stb", "GLX", "OpenGL", "glfw", "dl" }
end

-- Compiling with ImGui and its backends, and linking them.
function sdfgen_use_imgui()
   externalincludedirs(IMGUI_INCLUDE_DIRS)
   sdfgen_link_imgui()
end
