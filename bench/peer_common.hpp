// Shared plumbing of the peer benchmark drivers (peer_openvdb, peer_embree): the command line,
// a stopwatch, and sdfgen's own mesh loading, grid and field saving, so that a peer's field has
// exactly sdfgen's samples and can be compared value for value with `sdfgen bake`.
#pragma once
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>

namespace sdfgen::peer {

struct Options {
    std::string mesh;
    std::string output;
    int res = 64;
    float padding = 0.1f;
    int rays = 64;                // peer_embree only
    std::string method = "exact"; // peer_embree only: exact (point queries) or rays (nearest ray hit)
};

// Parses `NAME MESH.obj --res N [--padding F] [--rays N] -o OUT.sdf`; --rays only when withRays.
// Returns -1 to go on, otherwise the exit code (help printed or a usage error reported).
inline int parseOptions(CLI::App& app, Options& options, bool withRays, int argc, char** argv) {
    app.add_option("mesh", options.mesh, "triangle mesh (Wavefront OBJ)")->required();
    app.add_option("-o,--output", options.output, "field to write (sdfgen-text)")->required();
    app.add_option("--res", options.res, "voxels along the longest side of the padded bounding box")
        ->capture_default_str()->check(CLI::Range(1, 1 << 16));
    app.add_option("--padding", options.padding, "margin on every side, as a fraction of the longest side")
        ->capture_default_str()->check(CLI::NonNegativeNumber);
    if (withRays) {
        app.add_option("--rays", options.rays, "rays per sample for the inside/outside vote")
            ->capture_default_str()->check(CLI::Range(1, 1 << 20));
        app.add_option("--method", options.method, "distances: exact (point queries) or rays (nearest hit of the rays)")
            ->capture_default_str()->check(CLI::IsMember({"exact", "rays"}));
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    return -1;
}

// A parameter value as sdfgen's own method lines print it (%g: "0.1", not "0.100000").
inline std::string numberText(float value) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", double(value));
    return text;
}

class Stopwatch {
public:
    double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
    // Seconds since the last lap (or the start).
    double lap() {
        const Clock::time_point now = Clock::now();
        const double s = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        return s;
    }

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point start_ = Clock::now();
    Clock::time_point last_ = start_;
};

} // namespace sdfgen::peer
