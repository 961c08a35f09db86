// Fuzzes one field reader (the format of FUZZ_FIELD_EXTENSION, one harness per format): any input
// either loads into a consistent field or is an Error whose message is one line naming the file;
// what it accepts, the writer saves and the reader reads back identically (reader and writer agree).
// A band field's file (.npz, .vdb) goes through the sparse reader and writer the same way, and is
// made dense only where that is small.
#include "fuzz_input.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#ifndef FUZZ_FIELD_EXTENSION
#error "FUZZ_FIELD_EXTENSION names the format, e.g. \".sdf\""
#endif

namespace {

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    // memcmp of no bytes still wants pointers, which a band field without bricks has not.
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

void checkMessage(const sdfgen::Error& e, const std::string& path) {
    const std::string message = e.what();
    if (message.rfind(path, 0) != 0 || message.find('\n') != std::string::npos) {
        std::fprintf(stderr, "error message is not one line naming the file: %s\n", e.what());
        std::abort();
    }
}

} // namespace

bool sameSparse(const sdfgen::SparseField& a, const sdfgen::SparseField& b) {
    return sameBits(a.values(), b.values()) && a.bricks() == b.bricks() && a.insideBoxes() == b.insideBoxes() &&
           a.background() == b.background() && a.parameters == b.parameters && a.source == b.source && a.method == b.method &&
           a.grid().dims == b.grid().dims && a.grid().origin == b.grid().origin && a.grid().voxel == b.grid().voxel;
}

// A band field's file: loaded as it is (valid by construction), it round-trips exactly; its dense
// form, where small, is what loadField gives.
void fuzzSparse(const sdfgen::SparseField& field, const std::string& path) {
    const std::string copy = path + ".sparse" FUZZ_FIELD_EXTENSION;
    try {
        sdfgen::saveSparseField(field, copy);
        if (!sameSparse(sdfgen::loadSparseField(copy), field)) {
            std::fprintf(stderr, "sparse round trip changed the field\n");
            std::abort();
        }
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "the sparse reader accepted what the writer refuses: %s\n", e.what());
        std::abort();
    }
    if (field.grid().sampleCount() > (std::size_t(1) << 22)) return;
    try {
        const sdfgen::Field dense = sdfgen::loadField(path);
        if (!sameBits(dense.values, field.toDense().values) || dense.background != field.background()) {
            std::fprintf(stderr, "loadField differs from the sparse field's dense form\n");
            std::abort();
        }
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "loadField refused what loadAnyField read: %s\n", e.what());
        std::abort();
    }
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& path = sdfgen::fuzz::writeInput(data, size, FUZZ_FIELD_EXTENSION);
    sdfgen::AnyField loaded;
    try {
        loaded = sdfgen::loadAnyField(path);
    } catch (const sdfgen::Error& e) {
        checkMessage(e, path);
        return 0;
    }
    if (loaded.isBand()) {
        fuzzSparse(loaded.band(), path);
        return 0;
    }
    const sdfgen::Field& field = loaded.dense();
    if (field.values.size() != field.grid.sampleCount()) std::abort();
    if (!(field.grid.voxel > 0.0) || !std::isfinite(field.grid.voxel)) std::abort();
    for (float v : field.values) {
        if (!std::isfinite(v)) std::abort();
    }
    const std::string copy = path + ".copy" FUZZ_FIELD_EXTENSION;
    try {
        sdfgen::saveField(field, copy);
        const sdfgen::Field again = sdfgen::loadField(copy);
        if (!sameBits(again.values, field.values) || again.parameters != field.parameters || again.source != field.source ||
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
