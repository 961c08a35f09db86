#include "core/sign.hpp"
#include "core/parallel.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace sdfgen {

namespace {

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

// Upper bound of |winding number| of a (weighted) fan seen from p: area / (4π d²), d the distance
// to the fan.
double fanBound(const glm::dvec3& p, const Cap& cap) {
    const double d = glm::length(p - cap.centre) - cap.radius;
    return d > 0.0 ? cap.weight * cap.area / (4.0 * M_PI * d * d) : std::numeric_limits<double>::infinity();
}

// The fan's winding number at p, times its weight.
double fanWinding(const glm::dvec3& p, const Cap& cap) { return cap.weight * fanSolidAngle(p, cap) / (4.0 * M_PI); }

} // namespace

std::vector<Cap> makeCaps(const MeshTopology& topology) {
    // Equal loops (rotated to start at their smallest vertex) become one cap with a weight, so that
    // a stack of copies of an open triangle is one fan, evaluated once.
    std::map<std::vector<std::uint32_t>, int> loops;
    for (std::vector<std::uint32_t> loop : topology.boundaryLoops()) {
        std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
        ++loops[loop];
    }
    std::vector<Cap> caps;
    for (const auto& [loop, weight] : loops) {
        Cap cap;
        cap.weight = weight;
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

bool insideFromCrossings(const std::vector<Cap>& caps, const glm::dvec3& p, int ahead, int orientation) {
    // The fans' winding number is subtracted only where it could reach 1/2: near fans exactly,
    // far ones within their bounds, and all exactly when the bounds leave doubt.
    double far = 0.0;
    for (const Cap& cap : caps) far += fanBound(p, cap);
    if (far < 0.45) return orientation * ahead >= 1;
    double near = 0.0;
    far = 0.0;
    for (const Cap& cap : caps) {
        const double bound = fanBound(p, cap);
        if (bound < 0.02) far += bound;
        else near += fanWinding(p, cap);
    }
    double w = double(ahead) - near;
    if (std::fabs(orientation * w - 0.5) <= far) {
        for (const Cap& cap : caps) {
            if (fanBound(p, cap) < 0.02) w -= fanWinding(p, cap);
        }
    }
    return orientation * w > 0.5;
}

double windingFromCrossings(const std::vector<Cap>& caps, const glm::dvec3& p, int ahead) {
    double w = double(ahead);
    for (const Cap& cap : caps) w -= fanWinding(p, cap);
    return w;
}

int crossingsAhead(const Mesh& mesh, const Bvh& tree, const std::vector<Cap>& caps, const glm::dvec3& p) {
    // The same line and the same predicates as insideByWinding's row through p, so that a query at a
    // sample's position counts exactly the crossings its row scan counts ahead of it.
    const glm::vec3 line(p); // rows pass through float (y, z)
    int ahead = 0;
    auto count = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int weight) {
        int orientation;
        glm::dvec3 w;
        if (!pointInTriangle2d({line.y, line.z}, {a.y, a.z}, {b.y, b.z}, {c.y, c.z}, orientation, w)) return;
        if (w.x * a.x + w.y * b.x + w.z * c.x > p.x) ahead += orientation * weight;
    };
    Bounds ray;
    ray.min = glm::vec3(std::nextafter(float(p.x), -std::numeric_limits<float>::infinity()), line.y, line.z);
    ray.max = glm::vec3(std::numeric_limits<float>::infinity(), line.y, line.z);
    tree.forEachOverlap(ray, [&](std::uint32_t t) {
        count(glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)), int(tree.copies(t)));
    });
    for (const Cap& cap : caps) {
        for (std::size_t i = 0; i < cap.loop.size(); ++i) count(cap.loop[(i + 1) % cap.loop.size()], cap.loop[i], cap.centre, cap.weight);
    }
    return ahead;
}

double windingNumber(const Mesh& mesh, const glm::dvec3& p) {
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        sum += solidAngle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
    }
    return sum / (4.0 * M_PI);
}

std::vector<std::uint8_t> insideByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                          const RunControl& control, bool flipped) {
    const int orientation = flipped ? -1 : 1;
    const std::vector<Cap> caps = makeCaps(topology);
    const int nx = grid.dims.x, ny = grid.dims.y, nz = grid.dims.z;

    // 1. Signed crossings of every row's line (parallel to x) with the closed surface mesh + fans.
    struct Crossing {
        double x;
        int sign; // +weight where the surface faces +x: moving along +x leaves the solid there
    };
    std::vector<std::vector<Crossing>> rows(std::size_t(ny) * std::size_t(nz));
    const glm::dvec3 first = localPosition(mesh, grid, 0, 0, 0);
    const double h = grid.voxel / mesh.unit;
    auto addTriangle = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int weight) {
        // Candidate rows from the projected bounds, one wider each way; the exact test decides.
        const double ylo = std::min({a.y, b.y, c.y}), yhi = std::max({a.y, b.y, c.y});
        const double zlo = std::min({a.z, b.z, c.z}), zhi = std::max({a.z, b.z, c.z});
        const int j0 = std::max(0, int(std::floor((ylo - first.y) / h)) - 1);
        const int j1 = std::min(ny - 1, int(std::ceil((yhi - first.y) / h)) + 1);
        const int k0 = std::max(0, int(std::floor((zlo - first.z) / h)) - 1);
        const int k1 = std::min(nz - 1, int(std::ceil((zhi - first.z) / h)) + 1);
        for (int k = k0; k <= k1; ++k) {
            for (int j = j0; j <= j1; ++j) {
                const glm::vec3 s(localPosition(mesh, grid, 0, j, k)); // rows pass through float (y, z)
                int orientation;
                glm::dvec3 w;
                if (!pointInTriangle2d({s.y, s.z}, {a.y, a.z}, {b.y, b.z}, {c.y, c.z}, orientation, w)) continue;
                rows[std::size_t(k) * std::size_t(ny) + std::size_t(j)].push_back({w.x * a.x + w.y * b.x + w.z * c.x, orientation * weight});
            }
        }
    };
    // Copies of a triangle cross once, with their number as the weight.
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        if (const int weight = int(topology.copies(t))) {
            addTriangle(glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)), weight);
        }
    }
    for (const Cap& cap : caps) {
        for (std::size_t i = 0; i < cap.loop.size(); ++i) addTriangle(cap.loop[(i + 1) % cap.loop.size()], cap.loop[i], cap.centre, cap.weight);
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
            const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
            while (next < crossings.size() && crossings[next].x > p.x) ahead += crossings[next++].sign;
            const bool in = insideFromCrossings(caps, p, ahead, orientation);
            inside[grid.index(i, j, k)] = in;
        }
    });
    return inside;
}

std::vector<std::uint8_t> insideByPseudonormal(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                               const std::vector<std::uint32_t>& nearestTriangle, const RunControl& control) {
    std::vector<std::uint8_t> inside(grid.sampleCount());
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control, [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
        for (int i = 0; i < grid.dims.x; ++i) {
            const std::size_t index = grid.index(i, j, k);
            const std::uint32_t t = nearestTriangle[index];
            const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
            const ClosestPoint closest = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                                glm::dvec3(mesh.vertex(t, 2)));
            inside[index] = glm::dot(p - closest.point, topology.pseudonormal(t, closest.feature)) < 0.0;
        }
    });
    return inside;
}

} // namespace sdfgen
