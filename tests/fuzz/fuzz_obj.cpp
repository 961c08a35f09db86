// Fuzzes the OBJ loader: any input either loads into a valid mesh or is an Error; never a crash,
// a sanitizer report, a non-finite vertex or an index out of range.
#include "fuzz_input.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& path = sdfgen::fuzz::writeInput(data, size, ".obj");
    try {
        sdfgen::fuzz::checkMesh(sdfgen::loadObj(path));
    } catch (const sdfgen::Error&) {
    }
    return 0;
}
