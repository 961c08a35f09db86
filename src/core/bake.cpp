#include "core/bake.hpp"
#include "core/exact.hpp"
#include "core/ray_generator.hpp"
#include "core/sign.hpp"
#include "core/topology.hpp"
#include "sdfgen/error.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

namespace sdfgen {

const char* toString(DistanceMethod method) {
    switch (method) {
    case DistanceMethod::Rays: return "rays";
    case DistanceMethod::Exact: return "exact";
    case DistanceMethod::Brute: return "brute";
    }
    return "?";
}

const char* toString(SignMethod sign) {
    switch (sign) {
    case SignMethod::Default: return "default";
    case SignMethod::Auto: return "auto";
    case SignMethod::Rays: return "rays";
    case SignMethod::Pseudonormal: return "pseudonormal";
    case SignMethod::Winding: return "winding";
    }
    return "?";
}

namespace {

// Sign auto: pseudonormal when the mesh check proves it right, else winding; records why.
SignMethod chooseSign(const Mesh& mesh, const Bvh& tree, const MeshTopology& topology, const RunControl& control, BakeResult& result) {
    result.checked = true;
    result.check = topology.check(mesh, tree, control);
    if (result.check.closedAndClean()) {
        result.signReason = "pseudonormal: the mesh is closed, manifold, consistently oriented and free of self-intersections";
        return SignMethod::Pseudonormal;
    }
    const MeshCheck& c = result.check;
    std::string problems;
    for (const auto& [count, name] : {std::pair{c.boundaryEdges, "holes"}, {c.nonManifoldEdges, "non-manifold edges"},
                                      {c.inconsistentEdges, "flipped faces"}, {c.nonManifoldVertices, "pinched vertices"},
                                      {c.selfIntersections, "self-intersections"}}) {
        if (count) problems += std::string(problems.empty() ? "" : ", ") + name;
    }
    result.signReason = "winding: the mesh has " + problems;
    return SignMethod::Winding;
}

} // namespace

BakeResult bake(const Mesh& mesh, const Bvh& tree, const BakeSettings& settings, const RunControl& control) {
    const Grid grid = makeGrid(mesh.bounds, settings.res, settings.padding);
    if (settings.rays < 1) throw Error("rays per sample must be at least 1 (got " + std::to_string(settings.rays) + ")");
    BakeResult result;
    SignMethod sign = settings.sign;
    if (sign == SignMethod::Default) sign = settings.method == DistanceMethod::Rays ? SignMethod::Rays : SignMethod::Auto;
    const bool usesRays = settings.method == DistanceMethod::Rays || sign == SignMethod::Rays;

    Field& field = result.field;
    using Clock = std::chrono::steady_clock;
    auto since = [](Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); };
    const Clock::time_point start = Clock::now();
    if (settings.method == DistanceMethod::Brute) {
        if (sign != SignMethod::Auto && sign != SignMethod::Winding) {
            throw Error(std::string("the brute method signs by the exact winding number; --sign ") + toString(sign) +
                        " does not apply");
        }
        field = computeBruteForce(mesh, grid, control);
        result.sign = SignMethod::Winding;
        result.distanceSeconds = since(start);
    } else if (settings.method == DistanceMethod::Exact && sign != SignMethod::Rays) {
        // The sign method is settled first, so the exact pass writes (pseudonormal-)signed
        // distances straight into the field and the winding sign negates in place: the field is
        // the only per-sample array.
        const MeshTopology topology(mesh);
        if (sign == SignMethod::Auto) sign = chooseSign(mesh, tree, topology, control.phase(0.0, 0.1), result);
        result.signSeconds = since(start);
        const Clock::time_point distanceStart = Clock::now();
        field.values.resize(grid.sampleCount());
        computeExactField(mesh, tree, grid, sign == SignMethod::Pseudonormal ? &topology : nullptr, field.values.data(),
                          control.phase(0.1, sign == SignMethod::Winding ? 0.8 : 1.0));
        result.distanceSeconds = since(distanceStart);
        const Clock::time_point windingStart = Clock::now();
        if (sign == SignMethod::Winding) applyWindingSign(mesh, topology, grid, field.values.data(), control.phase(0.8, 1.0));
        result.signSeconds += since(windingStart);
        result.sign = sign;
        field.source = mesh.source;
        field.grid = grid;
    } else {
        // Distances first, then signs; each phase reports its share of the progress bar.
        std::vector<float> distance;
        NearestField nearest;
        Field rayField;
        if (usesRays) {
            rayField = generateRayField(mesh, tree, grid, settings.rays, control.phase(0.0, 0.5));
        }
        if (settings.method == DistanceMethod::Rays) {
            distance.resize(rayField.values.size());
            for (std::size_t i = 0; i < distance.size(); ++i) distance[i] = std::fabs(rayField.values[i]);
        }
        if (settings.method == DistanceMethod::Exact || sign == SignMethod::Pseudonormal) {
            nearest = computeNearest(mesh, tree, grid, control.phase(usesRays ? 0.5 : 0.0, 0.8));
            if (settings.method == DistanceMethod::Exact) distance = std::move(nearest.distance);
        }

        result.distanceSeconds = since(start);
        const Clock::time_point signStart = Clock::now();
        std::vector<std::uint8_t> inside;
        if (sign == SignMethod::Rays) {
            inside.resize(rayField.values.size());
            for (std::size_t i = 0; i < inside.size(); ++i) inside[i] = rayField.values[i] < 0.0f;
        } else {
            const MeshTopology topology(mesh);
            if (sign == SignMethod::Auto) sign = chooseSign(mesh, tree, topology, control.phase(0.8, 0.8), result);
            if (sign == SignMethod::Pseudonormal && nearest.triangle.empty()) {
                nearest = computeNearest(mesh, tree, grid, control.phase(0.5, 0.8)); // ray distances, auto chose pseudonormal
            }
            inside = sign == SignMethod::Pseudonormal ? insideByPseudonormal(mesh, topology, grid, nearest, control.phase(0.8, 1.0))
                                                      : insideByWinding(mesh, topology, grid, control.phase(0.8, 1.0));
        }
        result.sign = sign;
        result.signSeconds = since(signStart);
        field.source = mesh.source;
        field.grid = grid;
        field.values.resize(grid.sampleCount());
        for (std::size_t i = 0; i < field.values.size(); ++i) field.values[i] = inside[i] ? -distance[i] : distance[i];
    }

    field.method = toString(settings.method);
    field.parameters.clear();
    if (settings.method == DistanceMethod::Rays || result.sign == SignMethod::Rays) {
        field.parameters.emplace_back("rays", std::to_string(settings.rays));
    }
    const bool automatic = result.checked;
    field.parameters.emplace_back("sign", std::string(automatic ? "auto/" : "") + toString(result.sign));
    char padding[32];
    std::snprintf(padding, sizeof(padding), "%g", double(settings.padding));
    field.parameters.emplace_back("res", std::to_string(settings.res));
    field.parameters.emplace_back("padding", padding);
    return result;
}

} // namespace sdfgen
