#pragma once
#include "sdfgen/channels.hpp"
#include "sdfgen/grid.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sdfgen {

// What a dense field and a narrow-band one (sdfgen/sparse_field.hpp) both are: where their samples
// lie, how they were made, and which of their values are distances.
struct FieldHeader {
    std::string source;  // the mesh it was made from, as given
    std::string method;  // generator name, e.g. "rays"
    std::vector<std::pair<std::string, std::string>> parameters; // e.g. {"rays", "64"}
    Grid grid;
    // 0: every value is a distance. > 0: a narrow band (band * voxel; a SparseField, or one made dense
    // by SparseField::toDense): values with |value| < background are exact distances ("in the band",
    // OpenVDB's active voxels); the others are +background outside the solid and -background inside.
    float background = 0;

    // The value of parameter `key`, or "" when absent.
    std::string parameter(const std::string& key) const;
};

// A sampled signed distance field: negative inside the solid.
struct Field : FieldHeader {
    std::vector<float> values; // grid.sampleCount() values, x fastest
    // Channels a bake gives on request (BakeSettings::channels, see sdfgen/channels.hpp), in the
    // registry's order, none otherwise. Planar, each plane laid out as values: a 3-wide channel holds
    // every sample's x, then every y, then every z.
    std::vector<ChannelValues> channels;

    float at(int i, int j, int k) const { return values[grid.index(i, j, k)]; }
    // The channel called `name` ("gradient"), or null when the field has none.
    const ChannelValues* channel(const std::string& name) const { return findChannel(channels, name); }
};

} // namespace sdfgen
