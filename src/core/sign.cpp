#include "core/sign.hpp"
#include "core/parallel.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sdfgen {

namespace {

struct Triangle {
    glm::dvec3 a, b, c;
};

// A fan closing one boundary loop, with what bounds its winding number from afar.
struct Cap {
    std::vector<Triangle> triangles;
    glm::dvec3 centre;
    double radius = 0; // every point of the fan is within this of centre
    double area = 0;
};

std::vector<Cap> makeCaps(const MeshTopology& topology) {
    std::vector<Cap> caps;
    for (const std::vector<std::uint32_t>& loop : topology.boundaryLoops()) {
        Cap cap;
        cap.centre = glm::dvec3(0.0);
        for (std::uint32_t v : loop) cap.centre += topology.position(v);
        cap.centre /= double(loop.size());
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const glm::dvec3& from = topology.position(loop[i]);
            const glm::dvec3& to = topology.position(loop[(i + 1) % loop.size()]);
            // Reversed edge: the fan's boundary cancels the mesh's, so mesh + fans is closed.
            cap.triangles.push_back({to, from, cap.centre});
            cap.radius = std::max(cap.radius, glm::length(from - cap.centre));
            cap.area += 0.5 * glm::length(glm::cross(from - cap.centre, to - cap.centre));
        }
        caps.push_back(std::move(cap));
    }
    return caps;
}

} // namespace

double windingNumber(const Mesh& mesh, const glm::dvec3& p) {
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        sum += solidAngle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
    }
    return sum / (4.0 * M_PI);
}

std::vector<std::uint8_t> insideByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                          const RunControl& control) {
    const std::vector<Cap> caps = makeCaps(topology);
    const int nx = grid.dims.x, ny = grid.dims.y, nz = grid.dims.z;

    // 1. Signed crossings of every row's line (parallel to x) with the closed surface mesh + fans.
    struct Crossing {
        double x;
        int sign; // +1 where the surface faces +x: moving along +x leaves the solid there
    };
    std::vector<std::vector<Crossing>> rows(std::size_t(ny) * std::size_t(nz));
    const glm::dvec3 first(grid.sample(0, 0, 0));
    const double h = grid.voxel;
    auto addTriangle = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        // Candidate rows from the projected bounds, one wider each way; the exact test decides.
        const double ylo = std::min({a.y, b.y, c.y}), yhi = std::max({a.y, b.y, c.y});
        const double zlo = std::min({a.z, b.z, c.z}), zhi = std::max({a.z, b.z, c.z});
        const int j0 = std::max(0, int(std::floor((ylo - first.y) / h)) - 1);
        const int j1 = std::min(ny - 1, int(std::ceil((yhi - first.y) / h)) + 1);
        const int k0 = std::max(0, int(std::floor((zlo - first.z) / h)) - 1);
        const int k1 = std::min(nz - 1, int(std::ceil((zhi - first.z) / h)) + 1);
        for (int k = k0; k <= k1; ++k) {
            for (int j = j0; j <= j1; ++j) {
                const glm::vec3 s = grid.sample(0, j, k);
                int orientation;
                glm::dvec3 w;
                if (!pointInTriangle2d({s.y, s.z}, {a.y, a.z}, {b.y, b.z}, {c.y, c.z}, orientation, w)) continue;
                rows[std::size_t(k) * std::size_t(ny) + std::size_t(j)].push_back({w.x * a.x + w.y * b.x + w.z * c.x, orientation});
            }
        }
    };
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        addTriangle(glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
    }
    for (const Cap& cap : caps) {
        for (const Triangle& tri : cap.triangles) addTriangle(tri.a, tri.b, tri.c);
    }

    // 2. Per row: the closed surface's winding number is the signed count of crossings ahead (+x);
    //    then the fans' winding number is subtracted where it might matter.
    std::vector<std::uint8_t> inside(grid.sampleCount());
    parallelFor(rows.size(), control, [&](std::size_t row) {
        const int j = int(row % std::size_t(ny)), k = int(row / std::size_t(ny));
        std::vector<Crossing>& crossings = rows[row];
        std::sort(crossings.begin(), crossings.end(), [](const Crossing& l, const Crossing& r) { return l.x > r.x; });
        int ahead = 0;
        std::size_t next = 0;
        for (int i = nx - 1; i >= 0; --i) {
            const glm::dvec3 p(grid.sample(i, j, k));
            while (next < crossings.size() && crossings[next].x > p.x) ahead += crossings[next++].sign;
            // |w(fans)| <= area / (4π d²) with d the distance to the fan; below 1/2 it cannot flip
            // the integer's verdict (inside iff ahead >= 1).
            double bound = 0.0;
            for (const Cap& cap : caps) {
                const double d = glm::length(p - cap.centre) - cap.radius;
                bound += d > 0.0 ? cap.area / (4.0 * M_PI * d * d) : std::numeric_limits<double>::infinity();
                if (bound >= 0.45) break;
            }
            bool in = ahead >= 1;
            if (bound >= 0.45) {
                double fans = 0.0;
                for (const Cap& cap : caps)
                    for (const Triangle& tri : cap.triangles) fans += solidAngle(p, tri.a, tri.b, tri.c);
                in = double(ahead) - fans / (4.0 * M_PI) > 0.5;
            }
            inside[grid.index(i, j, k)] = in;
        }
    });
    return inside;
}

std::vector<std::uint8_t> insideByPseudonormal(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                               const NearestField& nearest, const RunControl& control) {
    std::vector<std::uint8_t> inside(grid.sampleCount());
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control, [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
        for (int i = 0; i < grid.dims.x; ++i) {
            const std::size_t index = grid.index(i, j, k);
            const std::uint32_t t = nearest.triangle[index];
            const glm::dvec3 p(grid.sample(i, j, k));
            const ClosestPoint closest = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                                glm::dvec3(mesh.vertex(t, 2)));
            inside[index] = glm::dot(p - closest.point, topology.pseudonormal(t, closest.feature)) < 0.0;
        }
    });
    return inside;
}

} // namespace sdfgen
