#pragma once
#include <string>
#include <vector>

namespace sdfgen::app {

// Opens the viewer window on `meshPaths` (a scene of several; none when empty) and runs until it is
// closed or Ctrl+Q. Returns the process exit code. Throws Error when no window can be opened.
int runViewer(const std::vector<std::string>& meshPaths);

} // namespace sdfgen::app
