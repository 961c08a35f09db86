#pragma once
// The one way every part of sdfgen reads a file's format from its name, so that `.OBJ`, `.Npy`
// and `.obj` choose the same reader or writer everywhere.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace sdfgen {

// The extension of `path`, dot included, in ASCII lower case (".obj"); empty when it has none.
inline std::string lowerExtension(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return extension;
}

} // namespace sdfgen
