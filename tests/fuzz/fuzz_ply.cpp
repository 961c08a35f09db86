// Fuzzes the PLY reader (src/core/mesh/ply_reader.cpp): any input either loads into a valid mesh or is
// an Error; never a crash, a sanitizer report, a hang or an allocation beyond what the file holds.
#include "fuzz_input.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& path = sdfgen::fuzz::writeInput(data, size, ".ply");
    try {
        sdfgen::fuzz::checkMesh(sdfgen::loadMesh(path));
    } catch (const sdfgen::Error&) {
    }
    return 0;
}
