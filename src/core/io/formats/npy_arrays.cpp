// Point arrays in and out of NumPy's .npy (sdfgen/formats.hpp): what `sdfgen query` and C++
// programs read points from and write answers to.
#include "core/io/atomic_file.hpp"
#include "core/io/formats/format.hpp"
#include "core/io/formats/npy.hpp"
#include "core/runtime/printable.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace sdfgen {

namespace {

template <class T>
void writeArray(const std::string& path, const std::string& descr, const std::vector<std::uint64_t>& shape, const std::vector<T>& values) {
    writeFileAtomically(path, [&](std::ostream& out) {
        const std::string header = formats::npyHeader(descr, false, shape);
        out.write(header.data(), std::streamsize(header.size()));
        out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(T)));
    });
}


// The number of values a shape holds, or Error naming `path` when the values given are not that many.
void checkShape(const std::string& path, const std::vector<std::uint64_t>& shape, std::size_t count) {
    std::uint64_t n = 1;
    for (const std::uint64_t extent : shape) {
        if (extent != 0 && n > UINT64_MAX / extent) throw Error(path + ": array shape overflows");
        n *= extent;
    }
    if (n != count) throw Error(path + ": " + std::to_string(count) + " values do not fill an array of " + std::to_string(n));
}

} // namespace

std::vector<double> loadPointsNpy(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    in.seekg(0, std::ios::end);
    const std::uint64_t fileBytes = std::uint64_t(in.tellg());
    in.seekg(0);
    const formats::ReadBytes read = [&](void* data, std::size_t size) {
        in.read(static_cast<char*>(data), std::streamsize(size));
        return std::size_t(in.gcount());
    };
    const formats::NpyHeader header = formats::readNpyHeader(read, path);
    if (header.descr != "<f4" && header.descr != "<f8") {
        throw Error(path + ": points must be float32 or float64 (dtype '" + printable(header.descr) + "')");
    }
    if (header.shape.size() != 2 || header.shape[1] != 3) throw Error(path + ": points must be an (N, 3) array");
    const std::uint64_t n = header.shape[0];
    const std::size_t item = header.itemSize();
    const std::uint64_t declared = header.dataBytes(path); // Error when it overflows
    if (fileBytes - header.headerBytes != declared) {
        throw Error(path + ": the file holds " + std::to_string(fileBytes - header.headerBytes) + " bytes of data, not the " +
                    std::to_string(declared) + " its header declares");
    }
    std::vector<char> raw(n * 3 * item);
    if (read(raw.data(), raw.size()) != raw.size()) throw Error(path + ": read error");
    std::vector<double> points(3 * n);
    for (std::uint64_t i = 0; i < n; ++i) {
        for (std::uint64_t a = 0; a < 3; ++a) {
            const std::uint64_t at = header.fortranOrder ? a * n + i : 3 * i + a;
            if (item == 4) {
                float v;
                std::memcpy(&v, raw.data() + at * 4, 4);
                points[3 * i + a] = v;
            } else {
                std::memcpy(&points[3 * i + a], raw.data() + at * 8, 8);
            }
        }
    }
    return points;
}


void saveNpy(const std::string& path, const std::vector<float>& values, const std::vector<std::uint64_t>& shape) {
    checkShape(path, shape, values.size());
    writeArray(path, "<f4", shape, values);
}

void saveNpy(const std::string& path, const std::vector<double>& values, const std::vector<std::uint64_t>& shape) {
    checkShape(path, shape, values.size());
    writeArray(path, "<f8", shape, values);
}

void saveNpy(const std::string& path, const std::vector<std::int64_t>& values, const std::vector<std::uint64_t>& shape) {
    checkShape(path, shape, values.size());
    writeArray(path, "<i8", shape, values);
}

} // namespace sdfgen
