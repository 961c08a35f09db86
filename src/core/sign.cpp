#include "core/sign.hpp"
#include "core/parallel.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sdfgen {

namespace {

// A fan closing one boundary loop, with what bounds its winding number from afar.
// Its triangles are (loop[i + 1], loop[i], centre): the loop reversed, so mesh + fans is closed.
struct Cap {
    std::vector<glm::dvec3> loop;
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
            cap.loop.push_back(from);
            cap.radius = std::max(cap.radius, glm::length(from - cap.centre));
            cap.area += 0.5 * glm::length(glm::cross(from - cap.centre, to - cap.centre));
        }
        caps.push_back(std::move(cap));
    }
    return caps;
}

// The fan's solid angle with a single atan2: each triangle contributes 2·arg(den + i·det) (Van
// Oosterom & Strackee), args add when the complex numbers multiply, and every crossing of the
// negative real axis is counted so that no turn is lost.
double fanSolidAngle(const glm::dvec3& p, const Cap& cap) {
    // Triangle (a, b, c) = (loop[i + 1], loop[i], centre): lengths and dot products with the
    // centre are shared by neighbouring triangles, so each loop vertex is measured once.
    const glm::dvec3 rc = cap.centre - p;
    const double lc = glm::length(rc);
    const std::size_t n = cap.loop.size();
    glm::dvec3 rb = cap.loop[0] - p;
    double lb = glm::length(rb), bc = glm::dot(rb, rc);
    double re = 1.0, im = 0.0;
    int turns = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 ra = cap.loop[(i + 1) % n] - p;
        const double la = glm::length(ra), ac = glm::dot(ra, rc);
        const double det = glm::dot(ra, glm::cross(rb, rc));
        const double den = la * lb * lc + glm::dot(ra, rb) * lc + bc * la + ac * lb;
        const double nextRe = re * den - im * det, nextIm = re * det + im * den;
        // Each factor turns by less than π, so a sign change of the imaginary part in the turning
        // direction means the product passed -1.
        if (det > 0.0 && im >= 0.0 && nextIm < 0.0) ++turns;
        else if (det < 0.0 && im < 0.0 && nextIm >= 0.0) --turns;
        const double scale = std::max(std::fabs(nextRe), std::fabs(nextIm));
        if (scale == 0.0) return 0.0; // p lies on a fan edge: the angle is undefined there
        re = nextRe / scale;
        im = nextIm / scale;
        rb = ra;
        lb = la;
        bc = ac;
    }
    return 2.0 * (std::atan2(im, re) + 2.0 * M_PI * turns);
}

// Upper bound of |winding number| of a fan seen from p: area / (4π d²), d the distance to the fan.
double fanBound(const glm::dvec3& p, const Cap& cap) {
    const double d = glm::length(p - cap.centre) - cap.radius;
    return d > 0.0 ? cap.area / (4.0 * M_PI * d * d) : std::numeric_limits<double>::infinity();
}

// Whether p is inside, given the closed surface's (mesh + fans) winding number `ahead` there: the
// fans' winding number is subtracted only where it could reach 1/2: near fans exactly, far ones
// within their bounds, and all exactly when the bounds leave doubt.
bool insideGivenClosedWinding(int ahead, const glm::dvec3& p, const std::vector<Cap>& caps) {
    double far = 0.0;
    for (const Cap& cap : caps) far += fanBound(p, cap);
    if (far < 0.45) return ahead >= 1;
    double near = 0.0;
    far = 0.0;
    for (const Cap& cap : caps) {
        const double bound = fanBound(p, cap);
        if (bound < 0.02) far += bound;
        else near += fanSolidAngle(p, cap) / (4.0 * M_PI);
    }
    double w = double(ahead) - near;
    if (std::fabs(w - 0.5) <= far) {
        for (const Cap& cap : caps) {
            if (fanBound(p, cap) < 0.02) w -= fanSolidAngle(p, cap) / (4.0 * M_PI);
        }
    }
    return w > 0.5;
}

// The closed surface whose winding number is counted: every mesh triangle, then every fan
// triangle (loop[i + 1], loop[i], centre), three corners each.
template <class AddTriangle>
void forEachClosedTriangle(const Mesh& mesh, const std::vector<Cap>& caps, AddTriangle&& addTriangle) {
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        addTriangle(glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
    }
    for (const Cap& cap : caps) {
        for (std::size_t i = 0; i < cap.loop.size(); ++i) addTriangle(cap.loop[(i + 1) % cap.loop.size()], cap.loop[i], cap.centre);
    }
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
                                          const RunControl& control, ComputeDevice* device) {
    const std::vector<Cap> caps = makeCaps(topology);
    if (device) {
        // The closed surface's winding numbers from the device, the fans' part here (as below).
        std::vector<glm::dvec3> closed;
        forEachClosedTriangle(mesh, caps, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
            closed.insert(closed.end(), {a, b, c});
        });
        const std::vector<std::int32_t> winding = device->windingNumbers(closed, grid, control.phase(0.0, caps.empty() ? 1.0 : 0.8));
        std::vector<std::uint8_t> inside(grid.sampleCount());
        if (caps.empty()) {
            for (std::size_t i = 0; i < inside.size(); ++i) inside[i] = winding[i] >= 1;
            return inside;
        }
        const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
        parallelFor(rows, control.phase(0.8, 1.0), [&](std::size_t row) {
            const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
            for (int i = 0; i < grid.dims.x; ++i) {
                const std::size_t index = grid.index(i, j, k);
                inside[index] = insideGivenClosedWinding(winding[index], glm::dvec3(grid.sample(i, j, k)), caps);
            }
        });
        return inside;
    }
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
    forEachClosedTriangle(mesh, caps, addTriangle);

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
            inside[grid.index(i, j, k)] = insideGivenClosedWinding(ahead, p, caps);
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
