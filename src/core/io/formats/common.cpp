// What every field format shares: the checks on saved and loaded fields, and the method line.
#include "core/io/formats/format.hpp"
#include "core/runtime/memory.hpp"
#include "sdfgen/error.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <system_error>

namespace sdfgen::formats {

namespace {

bool isToken(const std::string& s) {
    return !s.empty() && s.find_first_of(std::string_view(" \t\r\n=\0", 6)) == std::string::npos;
}

// The source and method line as the text format holds them: one line, the method and each
// parameter's key and value single words.
void checkNames(const std::string& source, const std::string& method, const std::vector<std::pair<std::string, std::string>>& parameters,
                const std::string& path) {
    if (source.find_first_of(std::string_view("\r\n\0", 3)) != std::string::npos) {
        throw Error(path + ": source name has a line break or NUL byte");
    }
    if (!isToken(method)) throw Error(path + ": method name '" + printable(method) + "' is not a single word");
    for (const auto& [key, value] : parameters) {
        if (!isToken(key) || !isToken(value)) throw Error(path + ": bad method parameter '" + printable(key + "=" + value) + "'");
    }
}

void checkValuesAndNames(const Field& field, const std::string& path) {
    if (field.values.size() != field.grid.sampleCount()) {
        throw Error(path + ": field has " + std::to_string(field.values.size()) + " values for a grid of " +
                    std::to_string(field.grid.sampleCount()));
    }
    for (std::size_t i = 0; i < field.values.size(); ++i) {
        if (!std::isfinite(field.values[i])) throw Error(path + ": value " + std::to_string(i) + " is not finite");
    }
    const std::size_t n = field.grid.sampleCount();
    for (const ChannelValues& channel : field.channels) checkChannelSize(channel, n, path, "a grid of " + std::to_string(n));
    checkNames(field.source, field.method, field.parameters, path);
}

} // namespace

void checkChannelSize(const ChannelValues& channel, std::size_t count, const std::string& path, const std::string& what) {
    const ChannelInfo* info = nullptr;
    for (const ChannelInfo& known : channelInfos()) {
        if (channel.name == known.name) info = &known;
    }
    if (!info) throw Error(path + ": unknown channel '" + printable(channel.name) + "'");
    const std::size_t size = channel.size();
    const bool typed = info->type == ChannelType::Int32 ? channel.floats.empty() : channel.ints.empty();
    if (!typed || size != std::size_t(info->width) * count) {
        throw Error(path + ": the " + channel.name + " channel has " + std::to_string(size) + (typed ? "" : " wrongly typed") + " values for " + what);
    }
}

void checkGrid(const Grid& grid, const std::string& path) {
    if (grid.dims.x < 1 || grid.dims.y < 1 || grid.dims.z < 1) throw Error(path + ": grid has no samples");
    if (Grid::checkedSampleCount(grid.dims) == 0) {
        throw Error(path + ": grid " + std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" + std::to_string(grid.dims.z) +
                    " has more than 2^58 samples");
    }
    if (!std::isfinite(grid.origin.x) || !std::isfinite(grid.origin.y) || !std::isfinite(grid.origin.z)) {
        throw Error(path + ": grid origin is not finite");
    }
    const double h = grid.voxel;
    auto text = [](double v) { // the shortest text that reads back as v
        char buffer[32];
        return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
    };
    if (!(h >= double(std::numeric_limits<float>::min())) || !(h <= double(std::numeric_limits<float>::max()))) {
        throw Error(path + ": voxel size " + text(h) + " is not a positive normal float32 (" +
                    text(std::numeric_limits<float>::min()) + " to " + text(std::numeric_limits<float>::max()) + ")");
    }
    for (int a = 0; a < 3; ++a) {
        const double low = grid.origin[a], high = grid.origin[a] + double(grid.dims[a]) * h;
        const double largest = std::max(std::fabs(low), std::fabs(high));
        if (!(largest <= double(std::numeric_limits<float>::max()))) {
            throw Error(path + ": grid (origin " + text(grid.origin.x) + " " + text(grid.origin.y) + " " + text(grid.origin.z) +
                        ", voxel size " + text(h) + ") reaches beyond float32's range");
        }
        // Neighbouring samples must be distinct points: a voxel size far below the spacing of the
        // numbers at the grid's coordinates would put them on top of each other.
        if (grid.dims[a] > 1 && h < largest * 0x1p-40) {
            throw Error(path + ": voxel size " + text(h) + " is too small for coordinates as large as " + text(largest) +
                        " (neighbouring samples would coincide)");
        }
    }
}

void checkField(const Field& field, const std::string& path) {
    checkGrid(field.grid, path);
    checkValuesAndNames(field, path);
}

void checkSparseField(const SparseField& field, const std::string& path) {
    checkGrid(field.grid(), path);
    checkNames(field.source, field.method, field.parameters, path);
}

float bandBackground(const Field& field) {
    if (field.background > 0) return field.background;
    const std::string text = field.parameter("band");
    double band = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), band);
    const float background = float(band * field.grid.voxel);
    const bool valid = !text.empty() && ec == std::errc() && end == text.data() + text.size() && background > 0 && std::isfinite(background);
    return valid ? background : float(3 * field.grid.voxel);
}

SparseField sparseFromDense(const Field& field, float background, const std::string& where) {
    constexpr int B = SparseField::kBrick;
    FieldHeader header = field;
    header.background = background;
    SparseField::Storage storage;
    const glm::ivec3 dims = field.grid.dims, bricks = (dims + (B - 1)) / B;
    std::vector<float> brick(SparseField::kBrickSamples);
    for (int bz = 0; bz < bricks.z; ++bz) {
        for (int by = 0; by < bricks.y; ++by) {
            int insideFrom = -1; // the first brick of the current run of inside bricks in this row
            for (int bx = 0; bx <= bricks.x; ++bx) {
                bool inBand = false, negative = false, positive = false;
                if (bx < bricks.x) {
                    const glm::ivec3 lo = glm::ivec3(bx, by, bz) * B;
                    std::fill(brick.begin(), brick.end(), background);
                    for (int k = lo.z; k < std::min(lo.z + B, dims.z); ++k)
                        for (int j = lo.y; j < std::min(lo.y + B, dims.y); ++j)
                            for (int i = lo.x; i < std::min(lo.x + B, dims.x); ++i) {
                                const float v = field.values[field.grid.index(i, j, k)];
                                inBand |= std::fabs(v) < background;
                                negative |= v < 0;
                                positive |= !(v < 0);
                                brick[std::size_t(((k - lo.z) * B + (j - lo.y)) * B + (i - lo.x))] = std::clamp(v, -background, background);
                            }
                }
                const bool stored = inBand || (negative && positive);
                const bool inside = bx < bricks.x && !stored && negative;
                if (inside && insideFrom < 0) insideFrom = bx;
                if (!inside && insideFrom >= 0) {
                    storage.insideBoxes.push_back(SparseField::insideBox(dims, insideFrom, bx, by, bz));
                    insideFrom = -1;
                }
                if (stored) {
                    storage.bricks.emplace_back(bx, by, bz);
                    storage.values.insert(storage.values.end(), brick.begin(), brick.end());
                }
            }
        }
    }
    return SparseField(header, std::move(storage), where);
}

void checkDimsFit(const std::uint64_t dims[3], const std::string& path) {
    double samples = 1.0;
    for (int a = 0; a < 3; ++a) {
        if (dims[a] < 1) throw Error(path + ": dimensions must be at least 1");
        if (dims[a] > std::uint64_t(std::numeric_limits<int>::max())) {
            throw Error(path + ": dimension " + std::to_string(dims[a]) + " is too large");
        }
        samples *= double(dims[a]);
    }
    if (Grid::checkedSampleCount(glm::ivec3(int(dims[0]), int(dims[1]), int(dims[2]))) == 0) {
        throw Error(path + ": dimensions " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) +
                    " have more than 2^58 samples");
    }
    const std::uint64_t memory = availableMemoryBytes();
    if (samples * sizeof(float) > (memory > 0 ? double(memory) : 0x1p62)) {
        throw Error(path + ": dimensions " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
                    std::to_string(dims[2]) + " too large: they need " + std::to_string(std::llround(samples * sizeof(float) / 0x1p20)) +
                    " MiB, more than the " + std::to_string(memory >> 20) + " MiB of memory available");
    }
}

namespace {
std::string methodLine(const std::string& method, const std::vector<std::pair<std::string, std::string>>& parameters) {
    std::string line = method;
    for (const auto& [key, value] : parameters) line += " " + key + "=" + value;
    return line;
}
} // namespace

std::string methodLine(const Field& field) { return methodLine(field.method, field.parameters); }
std::string methodLine(const SparseField& field) { return methodLine(field.method, field.parameters); }

void parseMethodLine(const std::string& line, Field& field, const std::string& path) {
    field.parameters.clear();
    std::size_t pos = 0;
    bool first = true;
    while (pos < line.size()) {
        const std::size_t end = std::min(line.find(' ', pos), line.size());
        const std::string item = line.substr(pos, end - pos);
        pos = end + 1;
        if (item.empty()) continue;
        if (first) {
            if (item.find('=') != std::string::npos) throw Error(path + ": method line '" + printable(line) + "' has no method name");
            field.method = item;
            first = false;
            continue;
        }
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == item.size() || item.find('=', eq + 1) != std::string::npos) {
            throw Error(path + ": method parameter '" + printable(item) + "' is not key=value");
        }
        field.parameters.emplace_back(item.substr(0, eq), item.substr(eq + 1));
    }
    if (first) throw Error(path + ": missing method name");
    if (line.find_first_of("\t\r\n") != std::string::npos) throw Error(path + ": method line has a tab or line break");
}

} // namespace sdfgen::formats
