#include "core/method/channels.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>

namespace sdfgen {

namespace {

// The unit gradient of the signed distance, (p - c) / |p - c| until signed (followsSign); where
// the float distance is 0, the nearest triangle's face normal, outward as the sign sees it.
ChannelPlugin gradientEntry() {
    ChannelPlugin channel;
    channel.info = {"gradient", "the unit gradient of the signed distance, the outward face normal where the distance is 0",
                    ChannelType::Float32, 3, ChannelVector::Direction, 0};
    channel.compute = [](const ChannelHit& hit, double* values) {
        const glm::dvec3 g = hit.distance == 0.0f ? glm::dvec3(hit.mesh.faceNormals[hit.triangle]) * (hit.flipped ? -1.0 : 1.0)
                                                  : (hit.position - hit.closest.point) / std::sqrt(hit.closest.distanceSquared);
        for (int a = 0; a < 3; ++a) values[a] = g[a];
    };
    channel.followsSign = true;
    return channel;
}

ChannelPlugin closestEntry() {
    ChannelPlugin channel;
    channel.info = {"closest", "the nearest surface point, world coordinates", ChannelType::Float32, 3, ChannelVector::Position, 0};
    channel.compute = [](const ChannelHit& hit, double* values) {
        const glm::dvec3 world = hit.mesh.toWorld(hit.closest.point);
        for (int a = 0; a < 3; ++a) values[a] = world[a];
    };
    return channel;
}

// Ties go to the lower index (the search's order); -1 where a sample has none.
ChannelPlugin triangleEntry() {
    ChannelPlugin channel;
    channel.info = {"triangle", "the nearest triangle's index", ChannelType::Int32, 1, ChannelVector::Plain, -1};
    channel.compute = [](const ChannelHit& hit, double* values) { values[0] = double(hit.triangle); };
    channel.refuses = [](const Mesh& mesh) -> std::string {
        return mesh.triangleCount() > std::size_t(INT32_MAX) ? "more than 2147483647 triangles for the triangle channel's int32 indices" : "";
    };
    return channel;
}

} // namespace

const std::vector<ChannelPlugin>& channelPlugins() {
    static const std::vector<ChannelPlugin> plugins = {gradientEntry(), closestEntry(), triangleEntry()};
    return plugins;
}

const std::vector<ChannelInfo>& channelInfos() {
    static const std::vector<ChannelInfo> infos = [] {
        std::vector<ChannelInfo> list;
        for (const ChannelPlugin& plugin : channelPlugins()) {
            if (plugin.info.width < 1 || plugin.info.width > ChannelInfo::kMaxWidth) throw Error(std::string("channel ") + plugin.info.name + ": width must be 1 to 4");
            list.push_back(plugin.info);
        }
        if (list.size() > Channels::kMax) throw Error("more channels registered than a Channels set holds");
        return list;
    }();
    return infos;
}

namespace {

std::string knownChannels() {
    std::string known = "sdf";
    for (const ChannelInfo& info : channelInfos()) known += std::string(", ") + info.name;
    return known;
}

// The registry index of `name`, or channelInfos().size().
std::size_t channelIndex(const std::string& name) {
    const std::vector<ChannelInfo>& infos = channelInfos();
    std::size_t c = 0;
    while (c < infos.size() && name != infos[c].name) ++c;
    return c;
}

} // namespace

const ChannelInfo& channelInfo(const std::string& name) {
    const std::size_t c = channelIndex(name);
    if (c == channelInfos().size()) throw Error("unknown channel '" + name + "' (expected a comma-separated list of " + knownChannels() + ")");
    return channelInfos()[c];
}

std::string describeChannels() {
    const std::vector<ChannelInfo>& infos = channelInfos();
    std::string text;
    for (std::size_t c = 0; c < infos.size(); ++c) {
        text += (c == 0 ? "" : c + 1 == infos.size() ? " and " : ", ") + std::string(infos[c].name) + " (" + infos[c].description + ")";
    }
    return text;
}

bool Channels::has(const std::string& name) const { return has(channelIndex(name)); }

Channels& Channels::add(const std::string& name) {
    bits |= std::uint64_t(1) << (&channelInfo(name) - channelInfos().data());
    return *this;
}

Channels Channels::all() {
    Channels channels;
    for (const ChannelInfo& info : channelInfos()) channels.add(info.name);
    return channels;
}

Channels parseChannels(const std::string& list) {
    Channels channels;
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        const std::string name = list.substr(start, comma - start);
        if (name != "sdf" && !(name.empty() && list.empty())) channels.add(name);
        start = comma + 1;
    }
    return channels;
}

std::string toString(const Channels& channels) {
    std::string list = "sdf";
    for (std::size_t c = 0; c < channelInfos().size(); ++c) {
        if (channels.has(c)) list += std::string(",") + channelInfos()[c].name;
    }
    return list;
}

const ChannelValues* findChannel(const std::vector<ChannelValues>& channels, const std::string& name) {
    for (const ChannelValues& channel : channels) {
        if (channel.name == name) return &channel;
    }
    return nullptr;
}

Channels channelsOf(const std::vector<ChannelValues>& channels) {
    Channels set;
    for (const ChannelValues& channel : channels) set.add(channel.name);
    return set;
}

void checkChannels(const Mesh& mesh, const Channels& channels) {
    for (std::size_t c = 0; c < channelPlugins().size(); ++c) {
        const ChannelPlugin& plugin = channelPlugins()[c];
        if (!channels.has(c) || !plugin.refuses) continue;
        const std::string why = plugin.refuses(mesh);
        if (!why.empty()) throw Error(mesh.source + ": " + why);
    }
}

ChannelWriter::ChannelWriter(const Channels& asked, std::size_t count, bool planar, std::vector<ChannelValues>& channels,
                             const RunControl& control)
    : count_(count), planar_(planar) {
    const std::vector<ChannelPlugin>& plugins = channelPlugins();
    std::size_t first = channels.size();
    for (std::size_t c = 0; c < plugins.size(); ++c) {
        if (!asked.has(c)) continue;
        ChannelValues values;
        values.name = plugins[c].info.name;
        const std::size_t size = std::size_t(plugins[c].info.width) * count;
        if (plugins[c].info.type == ChannelType::Int32) zeroFilled(values.ints, size, control);
        else zeroFilled(values.floats, size, control);
        channels.push_back(std::move(values));
    }
    // Pointers taken once every buffer is in place (push_back moves the vectors, not their data).
    for (std::size_t c = 0; c < plugins.size(); ++c) {
        if (!asked.has(c)) continue;
        ChannelValues& values = channels[first++];
        outputs_.push_back({&plugins[c], values.floats.data(), values.ints.data()});
    }
}

void ChannelWriter::write(std::size_t index, const ChannelHit& hit, bool negative) const {
    double values[ChannelInfo::kMaxWidth];
    for (const Output& out : outputs_) {
        const ChannelInfo& info = out.plugin->info;
        out.plugin->compute(hit, values);
        const bool negate = negative && out.plugin->followsSign;
        for (int a = 0; a < info.width; ++a) {
            const std::size_t at = planar_ ? std::size_t(a) * count_ + index : std::size_t(info.width) * index + std::size_t(a);
            if (out.ints) {
                out.ints[at] = std::int32_t(negate ? -values[a] : values[a]);
            } else {
                const float value = float(values[a]);
                out.floats[at] = negate ? -value : value;
            }
        }
    }
}

void signChannels(std::vector<ChannelValues>& channels, const std::vector<float>& values, const RunControl& control) {
    const std::size_t n = values.size();
    constexpr std::size_t kBlock = std::size_t(1) << 16;
    for (ChannelValues& channel : channels) {
        const ChannelPlugin* plugin = nullptr;
        for (const ChannelPlugin& p : channelPlugins()) {
            if (channel.name == p.info.name) plugin = &p;
        }
        if (!plugin || !plugin->followsSign) continue;
        const std::size_t width = std::size_t(plugin->info.width);
        parallelFor((n + kBlock - 1) / kBlock, quiet(control), [&](std::size_t block) {
            for (std::size_t i = block * kBlock; i < std::min(n, (block + 1) * kBlock); ++i) {
                if (!(values[i] < 0.0f)) continue;
                for (std::size_t a = 0; a < width; ++a) {
                    if (channel.ints.empty()) channel.floats[a * n + i] = -channel.floats[a * n + i];
                    else channel.ints[a * n + i] = -channel.ints[a * n + i];
                }
            }
        });
    }
}

} // namespace sdfgen
