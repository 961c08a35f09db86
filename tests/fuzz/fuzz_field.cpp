// Fuzzes the field reader: any input either loads into a consistent field or is an Error; what it
// accepts, the writer saves and the reader reads back identically (reader and writer agree).
// When loadField/fieldFormatExtensions() (include/sdfgen/formats.hpp) are implemented, the input
// should be loaded under every registered extension here.
#include "fuzz_input.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "core/formats/format.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& path = sdfgen::fuzz::writeInput(data, size, ".sdf");
    sdfgen::Field field;
    try {
        field = sdfgen::loadFieldText(path);
    } catch (const sdfgen::Error&) {
        return 0;
    }
    if (field.values.size() != field.grid.sampleCount()) std::abort();
    if (!(field.grid.voxel > 0.0f) || !std::isfinite(field.grid.voxel)) std::abort();
    for (float v : field.values) {
        if (!std::isfinite(v)) std::abort();
    }
    const std::string copy = path + ".copy.sdf";
    try {
        sdfgen::saveFieldText(field, copy);
        const sdfgen::Field again = sdfgen::loadFieldText(copy);
        if (again.values != field.values || again.parameters != field.parameters || again.source != field.source ||
            again.method != field.method || again.grid.dims != field.grid.dims || again.grid.origin != field.grid.origin ||
            again.grid.voxel != field.grid.voxel) {
            std::fprintf(stderr, "round trip changed the field\n");
            std::abort();
        }
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "the reader accepted what the writer refuses: %s\n", e.what());
        std::abort();
    }
    return 0;
}
