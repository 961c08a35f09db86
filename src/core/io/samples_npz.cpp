// Samples as NumPy .npz: points (n, 3) and sdf (n,), float32, and the channels asked for, through
// the field formats' .npz writer (stored zip members, written atomically).
#include "core/io/formats/format.hpp"
#include "core/io/formats/npy.hpp"
#include "core/runtime/file_extension.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/sample.hpp"

#include <string>

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
    for (const ChannelValues& channel : samples.channels) formats::checkChannelSize(channel, n, path, std::to_string(n) + " samples");
    std::vector<formats::NpzMember> members = {
        {"points.npy", formats::npyHeader("<f4", false, {n, 3}), samples.points.data(), 3 * n * sizeof(float)},
        {"sdf.npy", formats::npyHeader("<f4", false, {n}), samples.sdf.data(), n * sizeof(float)}};
    for (const ChannelValues& channel : samples.channels) {
        const ChannelInfo& info = channel.info();
        std::vector<std::uint64_t> shape{n};
        if (info.width > 1) shape.push_back(std::uint64_t(info.width));
        if (n > 0) members.push_back({channel.name + ".npy", formats::npyHeader(formats::npyType(info.type), false, shape), channel.data(), channel.size() * 4});
    }
    formats::writeNpz(path, members);
}

} // namespace sdfgen
