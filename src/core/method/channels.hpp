#pragma once
// Channels as plug-ins: each is an entry in channelPlugins() (channels.cpp) naming the channel
// (sdfgen::ChannelInfo: its name, type, width and how formats store it) and computing its values
// from a sample's closest hit. The exact distance's passes (dense bakes, the band's .vdb, point
// queries for samples) write every asked-for channel through a ChannelWriter; formats and front
// ends read only ChannelInfo (docs/extending.md).
#include "core/mesh/geometry.hpp"
#include "sdfgen/channels.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/run_control.hpp"

#include <glm/vec3.hpp>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sdfgen {

// The closest hit a sample's distance is measured with: what every channel is computed from.
struct ChannelHit {
    const Mesh& mesh;
    glm::dvec3 position;    // the sample, local coordinates
    ClosestPoint closest;   // its closest point on `triangle`, local coordinates
    std::uint32_t triangle; // the nearest triangle, an index into mesh.triangles
    float distance;         // the unsigned distance (world units) the field holds
    bool flipped;           // the sign found the mesh inside out
};

struct ChannelPlugin {
    ChannelInfo info;
    // The sample's info.width values, in double; stored rounded to info.type.
    void (*compute)(const ChannelHit& hit, double* values) = nullptr;
    // Its values are negated where the signed distance is negative (written before the sign is
    // known, as a direction away from the surface).
    bool followsSign = false;
    // Why `mesh` cannot have the channel, or "" (the int32 triangle index on over 2^31 triangles).
    std::string (*refuses)(const Mesh& mesh) = nullptr;
};
// The registry: channelInfos() lists their infos in this order.
const std::vector<ChannelPlugin>& channelPlugins();

// Throws Error when `mesh` cannot have one of `channels` (ChannelPlugin::refuses).
void checkChannels(const Mesh& mesh, const Channels& channels);

// The asked-for channels' buffers for `count` points, and where each point's values go.
class ChannelWriter {
public:
    // Allocates each channel of `asked` in `channels` (appended in the registry's order), laid out
    // planar (Field: every point's x, then every y, then every z) or interleaved (Samples: x y z).
    ChannelWriter(const Channels& asked, std::size_t count, bool planar, std::vector<ChannelValues>& channels, const RunControl& control);
    bool empty() const { return outputs_.empty(); }
    // Computes and stores point `index`'s channels from its hit. `negative`: its signed distance is
    // negative (followsSign channels are negated), when known; else signChannels does it later.
    void write(std::size_t index, const ChannelHit& hit, bool negative = false) const;

private:
    struct Output {
        const ChannelPlugin* plugin;
        float* floats;
        std::int32_t* ints;
    };
    std::vector<Output> outputs_;
    std::size_t count_;
    bool planar_;
};

// Negates the followsSign channels of a planar field where `values` (count of them) are negative.
void signChannels(std::vector<ChannelValues>& channels, const std::vector<float>& values, const RunControl& control);

} // namespace sdfgen
