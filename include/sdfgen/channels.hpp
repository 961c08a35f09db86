#pragma once
// Channels: what a bake or a set of samples gives per point besides the signed distance ("sdf",
// always there), each computed from the closest hit the exact distance is measured with (exact
// method, on the CPU). They are plug-ins listed in one registry (src/core/method/channels.cpp,
// docs/extending.md): the command line, the viewer, Python and the formats take their names, types
// and widths from channelInfos(), so adding one touches that file alone.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sdfgen {

enum class ChannelType { Float32, Int32 };

// What a 3-wide channel's vectors are, for formats that record it (OpenVDB's vector types).
enum class ChannelVector {
    Plain,     // a vector of no particular kind
    Direction, // a unit direction, as a gradient (covariant, normalized)
    Position,  // a point in the mesh's (world) coordinates (moved with them, e.g. by a normalization)
};

struct ChannelInfo {
    static constexpr int kMaxWidth = 4;
    const char* name;        // as --channels, the .npz members, the .vdb grids and Python's attributes spell it
    const char* description; // what it holds, for help texts and docstrings
    ChannelType type = ChannelType::Float32;
    int width = 1;           // values per sample: 1 to kMaxWidth (3 for a vector)
    ChannelVector vector = ChannelVector::Plain;
    double none = 0;         // the value of a sample that has none (outside a .vdb's band)
};
// Every channel, in the registry's order: the order of every list, file and returned tuple.
const std::vector<ChannelInfo>& channelInfos();
// The channel named `name`; throws Error naming it and listing the known names.
const ChannelInfo& channelInfo(const std::string& name);

// "a (what a holds), b (...) and c (...)": every channel, for help texts.
std::string describeChannels();

// A set of channels: bit c stands for channelInfos()[c].
struct Channels {
    static constexpr std::size_t kMax = 64; // channels a registry may list
    std::uint64_t bits = 0;
    bool any() const { return bits != 0; }
    bool has(std::size_t c) const { return c < kMax && (bits >> c & 1) != 0; }
    bool has(const std::string& name) const;
    Channels& add(const std::string& name); // throws Error for an unknown name
    bool operator==(const Channels& other) const { return bits == other.bits; }
    bool operator!=(const Channels& other) const { return bits != other.bits; }
    static Channels all();
};
// The channels a comma-separated list names ("sdf,gradient,closest,triangle"; "sdf" alone or "" for
// none besides the distance); throws Error naming an unknown one and listing the known names.
Channels parseChannels(const std::string& list);
// The list parseChannels reads, "sdf" first, then the channels in the registry's order.
std::string toString(const Channels& channels);

// One channel's values: info().width per point, of its type (floats or ints, the other empty);
// their layout is the container's (Field: planar; Samples: interleaved).
struct ChannelValues {
    std::string name;
    std::vector<float> floats;      // a Float32 channel's values
    std::vector<std::int32_t> ints; // an Int32 channel's values
    const ChannelInfo& info() const { return channelInfo(name); }
    std::size_t size() const { return floats.size() + ints.size(); }
    const void* data() const { return floats.empty() ? static_cast<const void*>(ints.data()) : floats.data(); }
};
// The channel called `name` among `channels`, or null.
const ChannelValues* findChannel(const std::vector<ChannelValues>& channels, const std::string& name);
// The set of channels `channels` holds.
Channels channelsOf(const std::vector<ChannelValues>& channels);

} // namespace sdfgen
