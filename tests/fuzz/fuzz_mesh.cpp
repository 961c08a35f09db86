// Fuzzes the other mesh readers through loadMesh: the first byte picks the format (OFF and STL,
// read by sdfgen; glTF and GLB, checked by sdfgen and read by Assimp; .xml and .dae, names under
// which Assimp may take a file for glTF by its content and the guard must check it all the same;
// .mesh.xml and .irr, whose importers open the files a model names), the rest is the file. Any
// input either loads into a valid mesh or is an Error; never a crash, a sanitizer report, a hang
// or an allocation beyond what the file holds.
#include "fuzz_input.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const extensions[] = {".off", ".stl", ".gltf", ".glb", ".xml", ".dae", ".mesh.xml", ".irr"};
    const std::string& path = sdfgen::fuzz::writeInput(data + 1, size - 1, extensions[data[0] % 8]);
    try {
        sdfgen::fuzz::checkMesh(sdfgen::loadMesh(path));
    } catch (const sdfgen::Error&) {
    }
    return 0;
}
