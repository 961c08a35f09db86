// Samples as NumPy .npz: points (n, 3) and sdf (n,), float32, through the field formats' .npz
// writer (stored zip members, written atomically).
#include "core/formats/format.hpp"
#include "core/formats/npy.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/sample.hpp"

#include <string>

namespace sdfgen {

void saveSamples(const Samples& samples, const std::string& path) {
    const std::size_t n = samples.size();
    if (samples.points.size() != 3 * n) {
        throw Error(path + ": samples have " + std::to_string(samples.points.size()) + " coordinates for " + std::to_string(n) + " points");
    }
    formats::writeNpz(path, {{"points.npy", formats::npyHeader("<f4", false, {n, 3}), samples.points.data(), 3 * n * sizeof(float)},
                             {"sdf.npy", formats::npyHeader("<f4", false, {n}), samples.sdf.data(), n * sizeof(float)}});
}

} // namespace sdfgen
