// Fuzzes the OBJ loader: any input either loads into a valid mesh or is an Error; never a crash,
// a sanitizer report, a non-finite vertex or an index out of range.
#include "fuzz_input.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"

#include <cmath>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& path = sdfgen::fuzz::writeInput(data, size, ".obj");
    try {
        const sdfgen::Mesh mesh = sdfgen::loadObj(path);
        if (mesh.triangles.empty() || mesh.triangles.size() != mesh.faceNormals.size()) std::abort();
        for (const glm::uvec3& t : mesh.triangles) {
            for (int c = 0; c < 3; ++c) {
                if (t[c] >= mesh.positions.size()) std::abort();
                const glm::vec3 p = mesh.positions[t[c]];
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
            }
        }
    } catch (const sdfgen::Error&) {
    }
    return 0;
}
