#pragma once
// Parts of the core that need big third-party libraries live in libraries of their own, opened on
// first use (OpenVDB: core/io/openvdb_plugin.hpp; Assimp: core/mesh/assimp_reader.hpp), so that a run that
// does not need them does not load them: a plain bake of an OBJ to .npy stays lean.
#include <string>

namespace sdfgen {

// Opens `library` (beside the object this code is in: libsdfgen.so, or the program that links the
// core statically; else wherever the dynamic loader looks) and returns its symbol `entry`. Throws
// Error naming `what` the library is for, and why it cannot be loaded.
void* openPlugin(const std::string& library, const char* entry, const std::string& what);

} // namespace sdfgen
