#pragma once
#include <string>

namespace sdfgen::app {

// Opens the viewer window on `meshPath` (none when empty) and runs until it is closed or Ctrl+Q.
// Returns the process exit code. Throws Error when no window can be opened.
int runViewer(const std::string& meshPath);

} // namespace sdfgen::app
