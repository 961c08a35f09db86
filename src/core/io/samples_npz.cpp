// Samples as NumPy .npz: points (n, 3) and sdf (n,), float32, and the channels asked for, through
// the field formats' .npz writer (stored zip members, written atomically).
#include "core/io/formats/format.hpp"
#include "core/io/formats/npy.hpp"
#include "core/runtime/file_extension.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/sample.hpp"

#include <string>
#include <tuple>

namespace sdfgen {

void checkSamplesPath(const std::string& path) {
    const std::string extension = lowerExtension(path);
    if (extension != ".npz") {
        throw Error(path + ": samples are written as .npz only; name the output *.npz" +
                    (extension.empty() ? std::string(" (it has no extension)") : " (not " + printable(extension) + ")"));
    }
}

void saveSamples(const Samples& samples, const std::string& path) {
    checkSamplesPath(path);
    const std::size_t n = samples.size();
    if (samples.points.size() != 3 * n) {
        throw Error(path + ": samples have " + std::to_string(samples.points.size()) + " coordinates for " + std::to_string(n) + " points");
    }
    for (const auto& [name, size, per] : {std::tuple{"gradient", samples.gradient.size(), 3}, {"closest", samples.closest.size(), 3},
                                          {"triangle", samples.triangle.size(), 1}}) {
        if (size != 0 && size != std::size_t(per) * n) {
            throw Error(path + ": the " + name + " channel has " + std::to_string(size) + " values for " + std::to_string(n) + " samples");
        }
    }
    std::vector<formats::NpzMember> members = {
        {"points.npy", formats::npyHeader("<f4", false, {n, 3}), samples.points.data(), 3 * n * sizeof(float)},
        {"sdf.npy", formats::npyHeader("<f4", false, {n}), samples.sdf.data(), n * sizeof(float)}};
    if (!samples.gradient.empty()) members.push_back({"gradient.npy", formats::npyHeader("<f4", false, {n, 3}), samples.gradient.data(), 3 * n * sizeof(float)});
    if (!samples.closest.empty()) members.push_back({"closest.npy", formats::npyHeader("<f4", false, {n, 3}), samples.closest.data(), 3 * n * sizeof(float)});
    if (!samples.triangle.empty()) {
        members.push_back({"triangle.npy", formats::npyHeader("<i4", false, {n}), samples.triangle.data(), n * sizeof(std::int32_t)});
    }
    formats::writeNpz(path, members);
}

} // namespace sdfgen
