#pragma once
#include <imgui.h>

namespace sdfgen::app {

// Text wrapped to the space left on the line, at spaces only: Dear ImGui's TextWrapped also breaks
// after '.' and ',', splitting numbers ("-3.\n73") and file names. A word wider than the line
// breaks after its last '/' that fits, else where it must.
void wrappedText(const char* format, ...) IM_FMTARGS(1);

} // namespace sdfgen::app
