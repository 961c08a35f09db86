#pragma once
// The one place that includes the OpenGL loader: glad's GL 4.5 core profile.
#include <glad/gl.h>

#include <string>

namespace sdfgen::render {

// Loads the GL entry points through `getProcAddress` for the current context and checks that it
// is OpenGL 4.5 or later. Throws Error (one line) otherwise.
void loadGl(GLADloadfunc getProcAddress, const std::string& contextName);

// In debug builds, routes GL debug output (errors, warnings) to stderr when the context supports it.
void installDebugOutput();

} // namespace sdfgen::render
