#pragma once
#include "sdfgen/channels.hpp"
#include "sdfgen/grid.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sdfgen {

// A sampled signed distance field: negative inside the solid.
struct Field {
    std::string source;  // the mesh it was made from, as given
    std::string method;  // generator name, e.g. "rays"
    std::vector<std::pair<std::string, std::string>> parameters; // e.g. {"rays", "64"}
    Grid grid;
    std::vector<float> values; // grid.sampleCount() values, x fastest
    // 0: every value is a distance. > 0: a narrow-band field made dense (SparseField::toDense): values
    // with |value| < background are exact distances; the others are +-background and tell only the side.
    float background = 0;
    // Channels a bake gives on request (BakeSettings::channels, see sdfgen/channels.hpp), in the
    // registry's order, none otherwise. Planar, each plane laid out as values: a 3-wide channel holds
    // every sample's x, then every y, then every z.
    std::vector<ChannelValues> channels;

    float at(int i, int j, int k) const { return values[grid.index(i, j, k)]; }
    // The value of parameter `key`, or "" when absent.
    std::string parameter(const std::string& key) const;
    // The channel called `name` ("gradient"), or null when the field has none.
    const ChannelValues* channel(const std::string& name) const { return findChannel(channels, name); }
};

} // namespace sdfgen
