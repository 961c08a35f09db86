// sdfgen::Model: the facade that owns a mesh, its tree and its topology, and runs bakes and point
// queries over them.
#include "sdfgen/model.hpp"
#include "core/bake/bake.hpp"
#include "core/accel/bvh.hpp"
#include "core/distance/exact.hpp"
#include "core/mesh/geometry.hpp"
#include "core/method/channels.hpp"
#include "core/runtime/parallel.hpp"
#include "core/sign/winding_sign.hpp"
#include "core/accel/topology.hpp"
#include "core/mesh/vertex_groups.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/grid.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

namespace sdfgen {

namespace {

// The trees of the dead models of a refit chain (models refit one from another), kept for the next
// refit to reuse their memory (Bvh's and WideBvh's refit constructors): an optimisation loop's step
// then writes into memory already mapped, instead of memory the system zeroes and maps in page by
// page, which cost as much as the refit itself. At most one of each per chain.
struct RefitSpares {
    std::mutex mutex;
    std::optional<Bvh> tree;
    std::optional<WideBvh> wide;

    template <class Tree>
    std::optional<Tree> take(std::optional<Tree>& spare) {
        std::lock_guard<std::mutex> lock(mutex);
        std::optional<Tree> taken = std::move(spare);
        spare.reset();
        return taken;
    }
};

// The tree a taken spare holds, or null; it lives until the end of the full expression that took it.
template <class Tree>
Tree* valueOrNull(std::optional<Tree>&& spare) {
    return spare ? &*spare : nullptr;
}

} // namespace

struct Model::Impl {
    Impl(Mesh m, const RunControl& control) : mesh(std::move(m)), tree(mesh, control) {}
    // A model that dies gives its trees to its refit chain's spares.
    ~Impl() {
        if (!spares_) return;
        std::lock_guard<std::mutex> lock(spares_->mutex);
        if (!spares_->tree) spares_->tree.emplace(std::move(tree));
        if (wideBuilt_.load(std::memory_order_acquire) && !spares_->wide) spares_->wide.emplace(std::move(*wide_));
    }
    // `m` is `previous`'s mesh with its vertices moved, grouped by `groups` as before (so the same
    // connectivity and triangle copies): the trees and, where `previous` had built it, the topology
    // are refit side by side; `previous`'s check (if made) is kept while the orientation holds (see check).
    Impl(Mesh m, const Impl& previous, std::shared_ptr<const VertexGroups> groups, const RunControl& control)
        : mesh(std::move(m)), tree(previous.tree, mesh, control, valueOrNull(previous.chainSpares()->take(previous.chainSpares()->tree))),
          groups_(std::move(groups)), spares_(previous.chainSpares()) {
        if (previous.checked_.load(std::memory_order_acquire)) previousCheck_ = previous.check_;
        const bool refitWide = previous.wideBuilt_.load(std::memory_order_acquire);
        const bool refitTopology = previous.topologyBuilt_.load(std::memory_order_acquire);
        parallelInvoke(
            control,
            [&] {
                if (!refitWide) return;
                std::call_once(wideOnce, [&] {
                    wide_.emplace(*previous.wide_, mesh, control, valueOrNull(spares_->take(spares_->wide)));
                    wideBuilt_.store(true, std::memory_order_release);
                });
            },
            [&] {
                if (!refitTopology) return;
                std::call_once(topologyOnce, [&] {
                    topology_.emplace(*previous.topology_, mesh, control);
                    topologyBuilt_.store(true, std::memory_order_release);
                });
            });
    }

    // Built on first use, with the control of that use (a cancelled build is retried by the next).
    // The wide tree serves the closest-point searches of bakes and queries alike.
    const WideBvh& wide(const RunControl& control = {}) const {
        std::call_once(wideOnce, [&] {
            wide_.emplace(mesh, tree, control);
            wideBuilt_.store(true, std::memory_order_release);
        });
        return *wide_;
    }
    const MeshTopology& topology(const RunControl& control = {}) const {
        std::call_once(topologyOnce, [&] {
            topology_.emplace(mesh, tree, control);
            topologyBuilt_.store(true, std::memory_order_release);
        });
        return *topology_;
    }
    const MeshCheck& check(const RunControl& control = {}) const {
        std::call_once(checkOnce, [&] {
            const MeshTopology& built = topology(control.phase(0.0, 0.5));
            const MeshCheck& edges = built.edgeCheck();
            const bool sameEdges = previousCheck_ && previousCheck_->boundaryEdges == edges.boundaryEdges &&
                                   previousCheck_->nonManifoldEdges == edges.nonManifoldEdges &&
                                   previousCheck_->inconsistentEdges == edges.inconsistentEdges &&
                                   previousCheck_->nonManifoldVertices == edges.nonManifoldVertices &&
                                   previousCheck_->insideOut == edges.insideOut;
            if (sameEdges) { // refit: the previous search's findings stand, the volume is the new one
                check_ = edges;
                check_.selfIntersections = previousCheck_->selfIntersections;
                check_.selfIntersectionsSearched = previousCheck_->selfIntersectionsSearched;
                check_.misorientedShells = previousCheck_->misorientedShells;
            } else {
                check_ = built.check(mesh, tree, control.phase(0.5, 1.0));
            }
            checked_.store(true, std::memory_order_release);
        });
        return check_;
    }

    // How the vertices group by position: the topology's when it is built, else found now; kept by
    // the models refit from this one.
    std::shared_ptr<const VertexGroups> groups(const RunControl& control = {}) const {
        std::call_once(groupsOnce, [&] {
            if (!groups_) groups_ = topologyBuilt_.load(std::memory_order_acquire) ? topology_->groups()
                                                                                   : std::make_shared<const VertexGroups>(mesh.positions, control);
        });
        return groups_;
    }

    // The spares of the refit chain this model is in, made when it is first refit.
    const std::shared_ptr<RefitSpares>& chainSpares() const {
        std::call_once(sparesOnce, [&] {
            if (!spares_) spares_ = std::make_shared<RefitSpares>();
        });
        return spares_;
    }

    // For the winding number output.
    const WindingCaps& caps(const RunControl& control = {}) const {
        std::call_once(capsOnce, [&] { caps_.emplace(topology(control)); });
        return *caps_;
    }
    // The sign's PointSide for this mesh, made on first use.
    const PointSide& pointSide(const SignMethodPlugin& sign, const RunControl& control = {}) const {
        std::lock_guard<std::mutex> lock(pointSidesMutex_);
        std::unique_ptr<PointSide>& side = pointSides_[sign.id];
        if (!side) {
            side = sign.atPoint(PointContext{mesh, tree, [this, &control]() -> const WideBvh& { return wide(control); },
                                             [this, &control]() -> const MeshTopology& { return topology(control); }});
        }
        return *side;
    }

    Mesh mesh;
    Bvh tree;

private:
    mutable std::once_flag wideOnce, topologyOnce, checkOnce, capsOnce, groupsOnce, sparesOnce;
    mutable std::shared_ptr<const VertexGroups> groups_;
    mutable std::shared_ptr<RefitSpares> spares_;
    mutable std::optional<WideBvh> wide_;
    mutable std::optional<MeshTopology> topology_;
    mutable MeshCheck check_;
    mutable std::atomic<bool> checked_{false}, wideBuilt_{false}, topologyBuilt_{false}; // set once made (for refit)
    std::optional<MeshCheck> previousCheck_; // a refit model's: the check of the model it was refit from
    mutable std::optional<WindingCaps> caps_;
    mutable std::mutex pointSidesMutex_;
    mutable std::map<SignMethod, std::unique_ptr<PointSide>> pointSides_;
};

namespace {

// Mesh::warnings and the zero-area triangles buildMesh dropped, through control.warn.
void warnAboutMesh(const Mesh& mesh, const RunControl& control) {
    if (!control.warn) return;
    if (mesh.droppedDegenerate > 0) {
        control.warn(mesh.source + ": dropped " + std::to_string(mesh.droppedDegenerate) + " zero-area triangles");
    }
    for (const std::string& warning : mesh.warnings) control.warn(warning);
}

// The thread count is checked and the cancel flag read before the long work starts, so that a bad
// count or an early Cancel is answered at once, not after the load.
const RunControl& checkedControl(const RunControl& control) {
    arenaSize(control);
    throwIfCancelled(control);
    return control;
}

} // namespace

Model Model::load(const std::string& path, const RunControl& control) {
    checkedControl(control);
    return Model(loadMesh(path), control);
}

Model::Model(Mesh mesh, const RunControl& control) {
    warnAboutMesh(mesh, checkedControl(control));
    impl_ = std::make_unique<Impl>(std::move(mesh), control);
}
Model Model::refit(Mesh moved, const RunControl& control) const {
    const Impl& m = *impl_;
    checkedControl(control);
    // The same triangles over vertices that group as before have the same connectivity and the
    // same exact copies: everything built on them stands, and only positions are measured again.
    // Anything else is built afresh, and decides as a new model does.
    if (moved.triangles != m.mesh.triangles) return Model(std::move(moved), control);
    std::shared_ptr<const VertexGroups> groups = m.groups(quiet(control));
    if (!groups->holdFor(moved.positions)) return Model(std::move(moved), control);
    warnAboutMesh(moved, control);
    // Each refit pass is a few streaming loops: below this many triangles they take less time than
    // waking the thread pool for them (and its threads' spinning between the passes), so they run
    // on the calling thread alone. Results never depend on the thread count.
    constexpr std::size_t kParallelRefit = std::size_t(1) << 17;
    RunControl refitControl = control;
    if (moved.triangleCount() < kParallelRefit) refitControl.threads = 1;
    Model result;
    result.impl_ = std::make_unique<Impl>(std::move(moved), m, std::move(groups), refitControl);
    return result;
}

Model::Model() = default;

Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;

const Mesh& Model::mesh() const { return impl_->mesh; }

const MeshCheck& Model::check(const RunControl& control) const { return impl_->check(control); }

BakeResult Model::bake(const BakeSettings& settings, const RunControl& control) const {
    const Impl& m = *impl_;
    checkedControl(control);
    if (const std::optional<SettingsProblem> refused = problem(settings)) throw Error(refused->message); // before the grid's own checks
    Grid grid;
    try {
        grid = bakeGrid(m.mesh.worldBounds(), settings);
    } catch (const Error& e) {
        throw Error(m.mesh.source + ": " + e.what());
    }
    // Topology and check, when a method needs them, are built inside the bake's phases: they honour
    // its cancel flag and threads, and report no progress of their own (it would run backwards).
    const RunControl lazy = quiet(control);
    const BakeContext context{m.mesh, m.tree, [&m, &lazy]() -> const WideBvh& { return m.wide(lazy); }, grid, settings,
                              [&m, &lazy]() -> const MeshTopology& { return m.topology(lazy); },
                              [&m, &lazy]() -> const MeshCheck& { return m.check(lazy); }};
    BakeResult result = sdfgen::bake(context, control);
    if (control.warn) {
        for (const std::string& warning : result.warnings) control.warn(m.mesh.source + ": " + warning);
    }
    return result;
}

namespace {

// The closest-point search runs in single precision in the mesh's local frame: exact near the
// mesh, but about a million mesh sizes away a point is rounded by more than the differences
// that decide its nearest triangle and sign (measured on the bundled bunny: wrong signs from
// 1e6 sizes on, none up to 1e5). Farther points are refused, not answered wrongly.
void refuseFarPoints(const Mesh& mesh, const double* points, std::size_t count) {
    constexpr double kFarthestQuery = 1e4; // in mesh sizes (the bounding box's longest side)
    const WorldBounds box = mesh.worldBounds();
    const glm::dvec3 extent = box.extent();
    const double size = std::max({extent.x, extent.y, extent.z});
    for (std::size_t i = 0; i < count; ++i) {
        const glm::dvec3 p(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
        const glm::dvec3 outside = glm::max(glm::max(box.min - p, p - box.max), glm::dvec3(0.0));
        const double away = std::max({outside.x, outside.y, outside.z});
        if (away > kFarthestQuery * size) {
            char message[320];
            std::snprintf(message, sizeof(message),
                          ": query point %zu (%.6g, %.6g, %.6g) is %.3g mesh sizes from the mesh's bounding box; points "
                          "are answered up to %.0f mesh sizes away (farther, single-precision searches cannot tell its "
                          "nearest triangle and sign)",
                          i, p.x, p.y, p.z, away / size, kFarthestQuery);
            throw Error(mesh.source + message);
        }
    }
}

// The points' indices in Morton order of their position, ties by index.
std::vector<std::uint32_t> mortonOrder(const Mesh& mesh, const double* points, std::size_t count) {
    std::vector<std::uint64_t> keys(count);
    const Bounds& box = mesh.bounds;
    const glm::dvec3 lo = glm::dvec3(box.min) - 1.0, size = glm::dvec3(box.extent()) + 2.0;
    auto spread = [](std::uint64_t v) { // 21 bits to every third bit
        v &= 0x1fffff;
        v = (v | v << 32) & 0x1f00000000ffffULL;
        v = (v | v << 16) & 0x1f0000ff0000ffULL;
        v = (v | v << 8) & 0x100f00f00f00f00fULL;
        v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
        v = (v | v << 2) & 0x1249249249249249ULL;
        return v;
    };
    for (std::size_t i = 0; i < count; ++i) {
        const glm::dvec3 q = glm::clamp((mesh.toLocal({points[3 * i], points[3 * i + 1], points[3 * i + 2]}) - lo) / size, 0.0, 1.0);
        const auto cell = [&](double c) { return std::uint64_t(c * double(0x1fffff)); };
        keys[i] = spread(cell(q.x)) | spread(cell(q.y)) << 1 | spread(cell(q.z)) << 2;
    }
    std::vector<std::uint32_t> order(count);
    for (std::size_t i = 0; i < count; ++i) order[i] = std::uint32_t(i);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b] || (keys[a] == keys[b] && a < b); });
    return order;
}

} // namespace

void Model::query(const double* points, std::size_t count, const PointQueryOutputs& out, SignMethod sign,
                  const RunControl& control) const {
    const Impl& m = *impl_;
    const Mesh& mesh = m.mesh;
    if (sign == SignMethod::Default) sign = SignMethod::Auto;
    // Channels from the same closest hits, as a bake computes them at its samples.
    std::optional<ChannelWriter> writer;
    if (out.channels.any()) {
        if (!out.channelValues) throw Error("point query channels asked with no channelValues to write them to");
        checkChannels(mesh, out.channels);
        writer.emplace(out.channels, count, false, *out.channelValues, control);
    }
    const ChannelWriter* channels = writer ? &*writer : nullptr;
    const bool needSign = out.signedDistance || out.gradient || channels;
    const bool needNearest = needSign || out.unsignedDistance || out.closestPoint || out.triangle || out.barycentric;
    if (needSign && !signMethod(sign).servesPointQueries()) {
        std::string known;
        const std::vector<Choice<SignMethod>> choices = pointQuerySignChoices();
        for (std::size_t i = 0; i < choices.size(); ++i) known += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + std::string(choices[i].name);
        throw Error("point queries sign by " + known + ", not " + toString(sign));
    }
    // Every sign a query takes reads the topology: built beside the wide tree (as in bake), each
    // alone leaving a core idle.
    if (needSign && signMethod(sign).readsTopology) {
        parallelInvoke(
            quiet(control), [&] { if (needNearest) m.wide(quiet(control)); }, [&] { m.topology(quiet(control)); });
    }
    // As bake: auto swaps the pseudonormal's inside and outside on an inside-out mesh (the winding
    // sign, |w| > 1/2, needs no swap).
    bool flipped = false;
    if (needSign) {
        const SignDecision decision = decideSign(
            sign, SignMethod::Auto, [&]() -> const MeshTopology& { return m.topology(quiet(control)); },
            [&]() -> const MeshCheck& { return m.check(quiet(control)); });
        flipped = decision.flipped;
        sign = decision.sign;
        if (control.warn) {
            for (const std::string& warning : decision.warnings) control.warn(mesh.source + ": " + warning);
        }
    }
    if (count > std::numeric_limits<std::uint32_t>::max()) throw Error("more than 4294967295 query points in one call");
    for (std::size_t i = 0; i < 3 * count; ++i) {
        if (!std::isfinite(points[i])) throw Error("query point " + std::to_string(i / 3) + " has a non-finite coordinate");
    }
    refuseFarPoints(mesh, points, count);
    // Build what the workers share before they start.
    const WideBvh* wide = needNearest ? &m.wide(quiet(control)) : nullptr;
    const PointSide* side = needSign ? &m.pointSide(signMethod(sign), quiet(control)) : nullptr;
    // Taken once: call_once's own fast path costs a thread-local write on every call.
    const WindingCaps* caps = out.windingNumber ? &m.caps(quiet(control)) : nullptr;

    // Points are visited in Morton order of their position, so that each point's search is seeded
    // by its neighbour's answer. Results do not depend on the order (the search is WideBvh's, ties
    // to the lower triangle index, as for the grid's samples), and the blocks are fixed, so they
    // never depend on the thread count either.
    const std::vector<std::uint32_t> order = mortonOrder(mesh, points, count);

    constexpr std::size_t kBlock = 256;
    const std::size_t blocks = (count + kBlock - 1) / kBlock;
    parallelFor(blocks, control, [&](std::size_t block) {
        const std::size_t begin = block * kBlock, end = std::min(count, begin + kBlock);
        std::uint32_t hint = WideBvh::kEmpty;
        glm::dvec3 local[kBlock];
        NearestPoint nearest[kBlock];
        std::uint8_t inside[kBlock];
        for (std::size_t at = begin; at < end; ++at) {
            const std::size_t index = order[at];
            local[at - begin] = mesh.toLocal({points[3 * index], points[3 * index + 1], points[3 * index + 2]});
            if (needNearest) {
                const glm::dvec3& p = local[at - begin];
                const std::uint32_t t = nearestTriangle(*wide, glm::vec3(p), hint);
                nearest[at - begin] = {t, closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                                 glm::dvec3(mesh.vertex(t, 2)))};
            }
        }
        if (needSign) side->inside(local, nearest, end - begin, flipped, inside);
        for (std::size_t at = begin; at < end; ++at) {
            const std::size_t index = order[at];
            const glm::dvec3& p = local[at - begin];
            if (needNearest) {
                const std::uint32_t t = nearest[at - begin].triangle;
                const ClosestPoint& closest = nearest[at - begin].closest;
                const float distance = float(std::sqrt(closest.distanceSquared) * mesh.unit);
                if (out.unsignedDistance) out.unsignedDistance[index] = distance;
                if (out.triangle) out.triangle[index] = std::int64_t(t);
                if (out.closestPoint) {
                    const glm::dvec3 world = mesh.toWorld(closest.point);
                    for (int a = 0; a < 3; ++a) out.closestPoint[3 * index + std::size_t(a)] = world[a];
                }
                if (out.barycentric) {
                    const glm::dvec3 w = barycentricOf(closest, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                       glm::dvec3(mesh.vertex(t, 2)));
                    for (int a = 0; a < 3; ++a) out.barycentric[3 * index + std::size_t(a)] = w[a];
                }
                if (needSign) {
                    const bool in = inside[at - begin] != 0;
                    if (out.signedDistance) out.signedDistance[index] = in ? -distance : distance;
                    if (out.gradient) {
                        // As the bake's gradient channel (core/method/channels.cpp's gradient entry, then signed by the value).
                        const glm::dvec3 g = distance == 0.0f ? glm::dvec3(mesh.faceNormals[t]) * (flipped ? -1.0 : 1.0)
                                                              : (p - closest.point) / std::sqrt(closest.distanceSquared) * (in ? -1.0 : 1.0);
                        for (int a = 0; a < 3; ++a) out.gradient[3 * index + std::size_t(a)] = g[a];
                    }
                    if (channels) channels->write(index, ChannelHit{mesh, p, closest, t, distance, flipped}, in && distance > 0.0f);
                }
            }
            if (out.windingNumber) {
                out.windingNumber[index] = caps->winding(p, crossingsAhead(mesh, m.tree, *caps, p));
            }
        }
    });
    // Never an infinity handed back as a distance: as bake, a mesh far beyond unit scale overflows float.
    for (float* distances : {out.signedDistance, out.unsignedDistance}) {
        if (distances && !std::all_of(distances, distances + count, [](float v) { return std::isfinite(v); })) {
            throw Error(mesh.source + ": distances overflow single precision at this mesh's scale; scale the mesh nearer to unit size");
        }
    }
}

namespace {

std::vector<double> flatten(const std::vector<glm::dvec3>& points) {
    std::vector<double> xyz(3 * points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        for (int a = 0; a < 3; ++a) xyz[3 * i + std::size_t(a)] = points[i][a];
    }
    return xyz;
}

} // namespace

std::vector<float> Model::signedDistance(const std::vector<glm::dvec3>& points, const RunControl& control) const {
    std::vector<float> result(points.size());
    PointQueryOutputs out;
    out.signedDistance = result.data();
    query(flatten(points).data(), points.size(), out, SignMethod::Auto, control);
    return result;
}

std::vector<float> Model::unsignedDistance(const std::vector<glm::dvec3>& points, const RunControl& control) const {
    std::vector<float> result(points.size());
    PointQueryOutputs out;
    out.unsignedDistance = result.data();
    query(flatten(points).data(), points.size(), out, SignMethod::Auto, control);
    return result;
}

std::vector<ClosestHit> Model::closest(const std::vector<glm::dvec3>& points, SignMethod sign, const RunControl& control) const {
    const std::size_t count = points.size();
    std::vector<float> distance(count);
    std::vector<double> point(3 * count), barycentric(3 * count), gradient(3 * count);
    std::vector<std::int64_t> triangle(count);
    PointQueryOutputs out;
    out.signedDistance = distance.data();
    out.closestPoint = point.data();
    out.barycentric = barycentric.data();
    out.gradient = gradient.data();
    out.triangle = triangle.data();
    query(flatten(points).data(), count, out, sign, control);
    std::vector<ClosestHit> hits(count);
    for (std::size_t i = 0; i < count; ++i) {
        ClosestHit& hit = hits[i];
        hit.triangle = triangle[i];
        hit.distance = distance[i];
        hit.sign = std::signbit(distance[i]) ? -1 : 1;
        for (int a = 0; a < 3; ++a) {
            hit.point[a] = point[3 * i + std::size_t(a)];
            hit.barycentric[a] = barycentric[3 * i + std::size_t(a)];
            hit.gradient[a] = gradient[3 * i + std::size_t(a)];
        }
    }
    return hits;
}

} // namespace sdfgen
