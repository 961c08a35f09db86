// peer_embree: an Intel Embree 3 baseline on the same mesh and grid as `sdfgen bake`.
//
//   peer_embree MESH.obj --res N [--padding 0.1] [--rays 64] [--method exact|rays] -o OUT.sdf
//
// Distance (--method exact, the default): the exact distance to the nearest triangle, by
// rtcPointQuery with a callback that computes the exact point-triangle distance and shrinks the
// query radius as closer triangles turn up. --method rays is sdfgen's `--method rays` on Embree:
// the distance is the nearest hit of the sign's rays (every ray traced, those after the vote is
// decided only as far as the nearest hit so far), or the distance to the mesh box's farthest
// corner when no ray hits. Sign: --rays rays per sample along sdfgen's spherical Fibonacci directions
// (sphereDirections: z_i = 1 - (2i+1)/N, phi_i = i * golden angle), traced as rtcIntersect8 packets
// of eight neighbouring samples; a sample is inside (negative) when more than half of the rays that
// hit anything first hit a back face, as in sdfgen's ray sign. A sample stops tracing once the
// remaining rays cannot change its vote, which never changes the result. Work is split over
// z-slices with TBB (all cores).
//
// Embree's geometric normal Ng of a triangle (v0, v1, v2) is (v1 - v0) x (v2 - v0): for sdfgen's
// counter-clockwise-from-outside triangles it points out of the solid (checked: a ray going down -z
// onto the triangle (0,0,0) (1,0,0) (0,1,0) reports Ng = +z). So a back face is dir . Ng > 0.
//
// Prints `embree: <s> s (scene <s>, distance <s>, sign <s>)`: the whole process from the start of
// loading to the end of saving, then the scene build, the distance pass and the sign pass (with
// --method rays the distance pass is part of the ray pass, reported as sign).
//
// Everything runs in the mesh's local coordinates, as in sdfgen (sample positions by
// localPosition, distances scaled by mesh.unit when stored).
#include "peer_common.hpp"

#include "core/accel/directions.hpp"
#include "core/mesh/sample_positions.hpp"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>
#if defined(__SSE3__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

namespace {

using namespace sdfgen;

// Embree's advice: flush denormals to zero on every thread that traces.
void flushDenormals() {
#if defined(__SSE3__)
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
}

// Squared distance from p to the triangle (a, b, c): the closest point by Voronoi regions of the
// vertices, edges and face (Ericson, Real-Time Collision Detection, 5.1.5), in double.
double pointTriangleDistanceSquared(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return glm::dot(ap, ap);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return glm::dot(bp, bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const glm::dvec3 q = a + (d1 / (d1 - d3)) * ab;
        return glm::dot(p - q, p - q);
    }
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return glm::dot(cp, cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const glm::dvec3 q = a + (d2 / (d2 - d6)) * ac;
        return glm::dot(p - q, p - q);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        const glm::dvec3 q = b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
        return glm::dot(p - q, p - q);
    }
    const double denominator = 1.0 / (va + vb + vc);
    const glm::dvec3 q = a + ab * (vb * denominator) + ac * (vc * denominator);
    return glm::dot(p - q, p - q);
}

struct ClosestQuery {
    const Mesh* mesh = nullptr;
    double distanceSquared = std::numeric_limits<double>::infinity();
};

// Called by rtcPointQuery for each triangle whose bounds meet the query sphere.
bool closestTriangle(RTCPointQueryFunctionArguments* args) {
    ClosestQuery& closest = *static_cast<ClosestQuery*>(args->userPtr);
    const Mesh& mesh = *closest.mesh;
    const glm::dvec3 p(args->query->x, args->query->y, args->query->z);
    const double d2 = pointTriangleDistanceSquared(p, mesh.vertex(args->primID, 0), mesh.vertex(args->primID, 1),
                                                   mesh.vertex(args->primID, 2));
    if (!(d2 < closest.distanceSquared)) return false;
    closest.distanceSquared = d2;
    const float radius = float(std::sqrt(d2));
    if (radius < args->query->radius) {
        args->query->radius = radius;
        return true;
    }
    return false;
}

void reportError(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "peer_embree: embree error %d: %s\n", int(code), message ? message : "");
}

int run(const peer::Options& options) {
    peer::Stopwatch clock;
    const Mesh mesh = loadMesh(options.mesh);
    const Grid grid = makeGrid(mesh.worldBounds(), options.res, options.padding);
    const std::vector<glm::vec3> directions = sphereDirections(options.rays);
    const bool raysMethod = options.method == "rays";
    clock.lap();

    RTCDevice device = rtcNewDevice(nullptr);
    if (!device) throw Error("cannot create an Embree device (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(device, reportError, nullptr);
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree's own buffers: they come with the padding its SIMD loads need past the last vertex.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.triangles.size()));
    if (!vertices || !indices) throw Error("cannot allocate Embree's geometry buffers");
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        for (int a = 0; a < 3; ++a) vertices[3 * v + a] = mesh.positions[v][a];
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int a = 0; a < 3; ++a) indices[3 * t + a] = mesh.triangles[t][a];
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    const double sceneSeconds = clock.lap();

    Field field;
    field.source = options.mesh;
    field.method = raysMethod ? "embree-rays" : "embree";
    field.parameters = {{"rays", std::to_string(options.rays)}, {"res", std::to_string(options.res)},
                        {"padding", peer::numberText(options.padding)}};
    field.grid = grid;
    field.values.assign(grid.sampleCount(), 0.0f);

    // Unsigned distances. Along a row, the distance is 1-Lipschitz: the previous sample's distance
    // plus one voxel bounds this one's, so the query starts with that radius (a little more, for
    // rounding) instead of infinity, and Embree skips every node farther away. Should nothing turn up
    // within it after all, the query runs again unbounded. The result is the exact nearest distance
    // either way.
    const float voxel = float(grid.voxel / mesh.unit); // in local units
    const float slack = 1e-4f * voxel;
    if (!raysMethod) tbb::parallel_for(tbb::blocked_range<int>(0, grid.dims.z, 1), [&](const tbb::blocked_range<int>& slices) {
        flushDenormals();
        for (int k = slices.begin(); k != slices.end(); ++k) {
            for (int j = 0; j < grid.dims.y; ++j) {
                float previous = std::numeric_limits<float>::infinity();
                for (int i = 0; i < grid.dims.x; ++i) {
                    const glm::vec3 p(localPosition(mesh, grid, i, j, k));
                    ClosestQuery closest;
                    closest.mesh = &mesh;
                    for (float radius = (previous + voxel) * 1.0001f + slack;; radius = std::numeric_limits<float>::infinity()) {
                        RTCPointQuery query;
                        query.x = p.x;
                        query.y = p.y;
                        query.z = p.z;
                        query.time = 0.0f;
                        query.radius = radius;
                        RTCPointQueryContext context;
                        rtcInitPointQueryContext(&context);
                        rtcPointQuery(scene, &query, &context, closestTriangle, &closest);
                        if (closest.distanceSquared < std::numeric_limits<double>::infinity() || std::isinf(radius)) break;
                    }
                    previous = float(std::sqrt(closest.distanceSquared));
                    field.values[grid.index(i, j, k)] = float(double(previous) * mesh.unit);
                }
            }
        }
    });
    const double distanceSeconds = clock.lap();

    // Signs: majority of back-face first hits among the rays that hit anything. Eight neighbouring
    // samples of a row trace each direction together as one rtcIntersect8 packet (parallel rays a
    // voxel apart: a coherent packet); a lane drops out once its vote is decided, or with --method
    // rays traces on only as far as its nearest hit.
    const int rays = int(directions.size());
    tbb::parallel_for(tbb::blocked_range<int>(0, grid.dims.z, 1), [&](const tbb::blocked_range<int>& slices) {
        flushDenormals();
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        RTCRayHit8 packet;
        alignas(32) int valid[8];
        for (int k = slices.begin(); k != slices.end(); ++k) {
            for (int j = 0; j < grid.dims.y; ++j) {
                for (int i0 = 0; i0 < grid.dims.x; i0 += 8) {
                    const int lanes = std::min(8, grid.dims.x - i0);
                    int back[8] = {}, front[8] = {};
                    float nearest[8];
                    std::fill(nearest, nearest + 8, std::numeric_limits<float>::infinity());
                    bool voting[8];
                    for (int r = 0; r < rays; ++r) {
                        const int remaining = rays - r;
                        int active = 0;
                        for (int l = 0; l < 8; ++l) {
                            voting[l] = l < lanes && !(back[l] > front[l] + remaining || front[l] >= back[l] + remaining);
                            const bool open = voting[l] || (raysMethod && l < lanes);
                            valid[l] = open ? -1 : 0;
                            active += open;
                            const glm::vec3 p(localPosition(mesh, grid, i0 + std::min(l, lanes - 1), j, k));
                            packet.ray.org_x[l] = p.x;
                            packet.ray.org_y[l] = p.y;
                            packet.ray.org_z[l] = p.z;
                            packet.ray.tnear[l] = 0.0f;
                            packet.ray.dir_x[l] = directions[r].x;
                            packet.ray.dir_y[l] = directions[r].y;
                            packet.ray.dir_z[l] = directions[r].z;
                            packet.ray.time[l] = 0.0f;
                            packet.ray.tfar[l] = voting[l] ? std::numeric_limits<float>::infinity() : nearest[l];
                            packet.ray.mask[l] = ~0u;
                            packet.ray.id[l] = unsigned(l);
                            packet.ray.flags[l] = 0;
                            packet.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
                            packet.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
                        }
                        if (active == 0) break; // every vote decided
                        rtcIntersect8(valid, scene, &context, &packet);
                        for (int l = 0; l < lanes; ++l) {
                            if (!valid[l] || packet.hit.geomID[l] == RTC_INVALID_GEOMETRY_ID) continue;
                            nearest[l] = std::min(nearest[l], packet.ray.tfar[l]);
                            if (!voting[l]) continue;
                            const float facing = packet.hit.Ng_x[l] * directions[r].x + packet.hit.Ng_y[l] * directions[r].y +
                                                 packet.hit.Ng_z[l] * directions[r].z;
                            (facing > 0.0f ? back[l] : front[l]) += 1;
                        }
                    }
                    for (int l = 0; l < lanes; ++l) {
                        float& value = field.values[grid.index(i0 + l, j, k)];
                        if (raysMethod) {
                            const glm::vec3 p(localPosition(mesh, grid, i0 + l, j, k));
                            const glm::vec3 far = glm::max(glm::abs(p - mesh.bounds.min), glm::abs(p - mesh.bounds.max));
                            value = float(double(back[l] + front[l] > 0 ? nearest[l] : glm::length(far)) * mesh.unit);
                        }
                        if (back[l] > front[l]) value = -value;
                    }
                }
            }
        }
    });
    const double signSeconds = clock.lap();

    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    saveField(field, options.output);
    std::printf("embree: %.3f s (scene %.3f, distance %.3f, sign %.3f)\n", clock.seconds(), sceneSeconds,
                distanceSeconds, signSeconds);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"peer_embree: sdfgen's grid, filled with Embree point queries (distance) and rays (sign)"};
    sdfgen::peer::Options options;
    if (const int code = sdfgen::peer::parseOptions(app, options, true, argc, argv); code >= 0) return code;
    try {
        return run(options);
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "peer_embree: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "peer_embree: %s: %s\n", options.mesh.c_str(), e.what());
    }
    return 1;
}
