#include "core/bake/bake.hpp"
#include "core/bake/band_bake.hpp"
#include "core/bake/memory_estimate.hpp"
#include "core/distance/exact.hpp"
#include "core/method/channels.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"
#include "core/runtime/out_of_memory.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <utility>

namespace sdfgen {

namespace {
BakeResult bakeContext(const BakeContext& context, const RunControl& control) {
    const BakeSettings& settings = context.settings;
    if (const std::optional<SettingsProblem> refused = problem(settings)) throw Error(refused->message);
    const DistanceMethodPlugin& method = distanceMethod(settings.method);
    SignMethod sign = settings.sign == SignMethod::Default ? method.defaultSign : settings.sign;
    const bool banded = settings.band != 0;
    const Channels& channels = settings.channels;
    checkChannels(context.mesh, channels);
    BakeResult result;
    BakeContext deviceContext = context;
    deviceContext.nearestRows = [&context](const NearestRowStore& store, const RunControl& rowControl) {
        forEachNearestRow(context.mesh, context.wide(), context.grid, store, rowControl);
    };
    if (banded) {
        result.deviceReason = "cpu: the narrow-band bake runs on the CPU only";
    } else if (channels.any()) {
        result.deviceReason = "cpu: asked for channels " + toString(channels).substr(4) + " (made on the CPU only)";
    } else if (method.onDevice) {
        deviceContext.device = selectComputeDevice(settings.device, &result.deviceReason);
        result.onDevice = deviceContext.device != nullptr;
    }
    if (banded) {
        const double needed = double(estimateBandBakeBytes(context.mesh, context.grid, settings.band));
        const std::uint64_t available = availableMemoryBytes();
        if (available > 0 && needed > double(available)) {
            const Grid& g = context.grid;
            throw Error("a band of " + std::to_string(settings.band) + " voxels on grid " + std::to_string(g.dims.x) + "x" +
                        std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z) + " needs about " + mebibytes(needed) +
                        " but only " + mebibytes(double(available)) + " of memory is available");
        }
    } else {
        checkBakeMemory(context.mesh, context.tree, context.grid, settings, result.onDevice, quiet(control));
    }

    using Clock = std::chrono::steady_clock;
    auto since = [](Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); };
    // What the passes will read of the mesh's structures is built first (if not built yet), the
    // wide tree and the topology at once: each alone leaves a core idle for much of its build.
    const Clock::time_point setupStart = Clock::now();
    const bool readsWide = (method.readsWideTree && !result.onDevice) || (!method.fixedSign && signMethod(sign).readsWideTree);
    const bool readsTopology = (!method.fixedSign && signMethod(sign).readsTopology) || banded;
    if (readsWide && readsTopology) {
        parallelInvoke(quiet(control), [&] { context.wide(); }, [&] { context.topology(); });
    } else if (readsWide) {
        context.wide();
    } else if (readsTopology) {
        context.topology();
    }
    result.setupSeconds = since(setupStart);
    // The sign is settled first (auto checks the mesh), so that a method that can sign as it
    // measures (exact with the pseudonormal) writes the signed field in one pass.
    const Clock::time_point checkStart = Clock::now();
    BakeContext methodContext = deviceContext;
    if (!method.fixedSign) {
        SignDecision decision = decideSign(sign, method.defaultSign, context.topology, context.check);
        sign = decision.sign;
        result.checked = decision.checked;
        result.check = decision.check;
        result.signReason = std::move(decision.reason);
        result.warnings = std::move(decision.warnings);
        methodContext.flipped = decision.flipped;
        methodContext.sign = sign;
    }
    if (banded && signMethod(sign).band == BandSigning::WhereProven && !result.checked && !context.check().closedAndClean()) {
        // Out of the band a sample has no distance pass to take a closest feature from: its side
        // is the winding sign's, which is the pseudonormal's only where the check proves it right.
        throw Error(std::string("a band bake takes sign ") + signMethod(sign).name +
                    " only for meshes it is proven right on (closed, manifold, consistently oriented, without self-intersections); "
                    "choose sign winding or auto");
    }
    const double checkSeconds = since(checkStart);
    releaseFreedMemory(); // the setup phases' scratch, before the field is allocated

    // The field's method line, e.g. "exact sign=auto/winding res=128 padding=0.1".
    auto parameters = [&](SignMethod used) {
        std::vector<std::pair<std::string, std::string>> list;
        if (method.castsRays || signMethod(used).castsRays) list.emplace_back("rays", std::to_string(settings.rays));
        list.emplace_back("sign", std::string(result.checked ? "auto/" : "") + toString(used));
        char number[32];
        list.emplace_back("res", std::to_string(settings.res));
        std::snprintf(number, sizeof(number), "%g", settings.padding);
        list.emplace_back("padding", number);
        if (banded) {
            std::snprintf(number, sizeof(number), "%g", settings.band);
            list.emplace_back("band", number);
        }
        return list;
    };
    if (banded) {
        SparseField field = bakeBand(methodContext, result, control);
        result.sign = sign;
        result.signSeconds += checkSeconds;
        field.method = method.name;
        field.parameters = parameters(sign);
        result.field = std::move(field);
        return result;
    }

    const Clock::time_point start = Clock::now();
    const bool signsInline = !method.fixedSign && sign == method.signsInline;
    const auto measure = methodContext.device ? method.onDevice : method.dense;
    DistancePass pass = measure(methodContext, control.phase(0.0, signsInline ? 1.0 : 0.7));
    result.distanceSeconds = since(start);
    releaseFreedMemory(); // the distance pass's scratch, before the sign pass's

    // Signs are applied to the distances in place, and side arrays released as soon as they are used.
    const Clock::time_point signStart = Clock::now();
    if (method.fixedSign) {
        sign = method.defaultSign;
        negateInside(pass.distance, *pass.inside);
    } else if (!pass.signedAsAsked) {
        const SignMethodPlugin& signer = signMethod(sign);
        (methodContext.device && signer.onDevice ? signer.onDevice : signer.dense)(methodContext, pass, control.phase(0.7, 1.0));
    }
    pass.inside.reset();
    result.sign = sign;
    result.signSeconds = checkSeconds + since(signStart);

    Field field;
    field.source = context.mesh.source;
    field.grid = context.grid;
    field.values = std::move(pass.distance);
    signChannels(pass.channels, field.values, control);
    field.channels = std::move(pass.channels);
    // Never a silently wrong field: float distances overflow on meshes far beyond unit scale.
    if (!std::all_of(field.values.begin(), field.values.end(), [](float v) { return std::isfinite(v); })) {
        throw Error(context.mesh.source + ": distances overflow single precision at this mesh's scale; scale the mesh nearer to unit size");
    }
    field.method = method.name;
    field.parameters = parameters(result.sign);
    result.field = std::move(field);
    return result;
}

} // namespace

BakeResult bake(const BakeContext& context, const RunControl& control) {
    const Grid& g = context.grid;
    const std::string grid = std::to_string(g.dims.x) + "x" + std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z);
    return namingOutOfMemory(context.mesh.source, ("baking its " + grid + " grid").c_str(), [&] { return bakeContext(context, control); });
}

BakeResult bake(const Mesh& mesh, const Bvh& tree, const BakeSettings& settings, const RunControl& control) {
    if (const std::optional<SettingsProblem> refused = problem(settings)) throw Error(refused->message); // before the grid's own checks
    const Grid grid = bakeGrid(mesh.worldBounds(), settings);
    std::optional<WideBvh> wide;
    std::optional<MeshTopology> topology;
    std::optional<MeshCheck> check;
    const RunControl lazy = quiet(control); // built inside the bake's phases (see Model::bake)
    auto wideOf = [&]() -> const WideBvh& {
        if (!wide) wide.emplace(mesh, tree, lazy);
        return *wide;
    };
    auto topologyOf = [&]() -> const MeshTopology& {
        if (!topology) topology.emplace(mesh, tree, lazy);
        return *topology;
    };
    const BakeContext context{mesh, tree, wideOf, grid, settings, topologyOf, [&]() -> const MeshCheck& {
                                  if (!check) check = topologyOf().check(mesh, tree, lazy);
                                  return *check;
                              }};
    return bake(context, control);
}

} // namespace sdfgen
