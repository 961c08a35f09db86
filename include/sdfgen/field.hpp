#pragma once
#include "sdfgen/grid.hpp"

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

    float at(int i, int j, int k) const { return values[grid.index(i, j, k)]; }
    // The value of parameter `key`, or "" when absent.
    std::string parameter(const std::string& key) const;
};

} // namespace sdfgen
