#pragma once
// OpenVDB is opened only when a .vdb file is read or written or an iso-surface is extracted
// (core/runtime/plugin.hpp): libopenvdb's 24 MB of symbol names, which the dynamic loader reads through as
// it relocates the library, would otherwise cost every run (a plain bake included) about 25 MB of
// resident memory and 20 ms. The code that uses it is libsdfgen_openvdb.so (src/vdb/).
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/sparse_field.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

namespace sdfgen {

struct OpenVdbPlugin {
    void (*save)(const Field& field, const std::string& path, const SaveOptions& options);
    AnyField (*load)(const std::string& path, const RunControl& control); // loadAnyField's
    // openvdb::tools::volumeToMesh of the field at `iso`: world positions, triangles and quads as
    // OpenVDB winds them.
    void (*polygons)(const Field& field, double iso, double adaptivity, std::vector<glm::vec3>& points,
                     std::vector<glm::uvec3>& triangles, std::vector<glm::uvec4>& quads);
    // The same for band fields: a level set written straight from the bricks (and read back as
    // bricks by load), and meshed as a level set, never made dense.
    void (*saveSparse)(const SparseField& field, const std::string& path);
    void (*saveSparseGivenUp)(SparseField&& field, const std::string& path); // saveSparseField(SparseField&&)
    void (*polygonsSparse)(const SparseField& field, double iso, double adaptivity, std::vector<glm::vec3>& points,
                           std::vector<glm::uvec3>& triangles, std::vector<glm::uvec4>& quads);
};

// The entry point the plugin exports.
constexpr const char* kOpenVdbPluginEntry = "sdfgen_openvdb_plugin";
using OpenVdbPluginEntry = const OpenVdbPlugin* (*)();

// Opens the plugin on first use; throws Error (naming the library and why) when it cannot.
const OpenVdbPlugin& openVdbPlugin();

} // namespace sdfgen
