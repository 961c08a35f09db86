#include "core/mesh/geometry.hpp"

#include <glm/geometric.hpp>
#include <cmath>

namespace sdfgen {

ClosestPoint closestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    auto result = [&](const glm::dvec3& q, TriangleFeature f) {
        const glm::dvec3 d = p - q;
        return ClosestPoint{q, glm::dot(d, d), f};
    };
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return result(a, TriangleFeature::VertexA);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return result(b, TriangleFeature::VertexB);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
        return result(a + ab * (d1 / (d1 - d3)), TriangleFeature::EdgeAB);
    }
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return result(c, TriangleFeature::VertexC);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
        return result(a + ac * (d2 / (d2 - d6)), TriangleFeature::EdgeCA);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
        return result(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), TriangleFeature::EdgeBC);
    }
    // Inside the face region: project onto the plane. The region tests above are rounding noise
    // for a (nearly) zero-area triangle, whose nearest point is then on one of its edges.
    const glm::dvec3 n = glm::cross(ab, ac);
    const double nn = glm::dot(n, n);
    if (nn > 1e-24 * glm::dot(ab, ab) * glm::dot(ac, ac)) {
        return result(p - n * (glm::dot(ap, n) / nn), TriangleFeature::Face);
    }
    ClosestPoint best = result(a, TriangleFeature::VertexA);
    const glm::dvec3 corners[3] = {a, b, c};
    const TriangleFeature edges[3] = {TriangleFeature::EdgeAB, TriangleFeature::EdgeBC, TriangleFeature::EdgeCA};
    for (int e = 0; e < 3; ++e) {
        const glm::dvec3 s = corners[e], d = corners[(e + 1) % 3] - s;
        const double len2 = glm::dot(d, d);
        const double t = len2 > 0.0 ? glm::clamp(glm::dot(p - s, d) / len2, 0.0, 1.0) : 0.0;
        const ClosestPoint candidate = result(s + d * t, edges[e]);
        if (candidate.distanceSquared < best.distanceSquared) best = candidate;
    }
    return best;
}

glm::dvec3 barycentricOf(const ClosestPoint& closest, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    // closest.point = from + t (to - from): weight 1 - t on `from`, t on `to`.
    auto along = [&closest](const glm::dvec3& from, const glm::dvec3& to) {
        const glm::dvec3 d = to - from;
        return glm::dot(closest.point - from, d) / glm::dot(d, d);
    };
    switch (closest.feature) {
    case TriangleFeature::VertexA: return {1.0, 0.0, 0.0};
    case TriangleFeature::VertexB: return {0.0, 1.0, 0.0};
    case TriangleFeature::VertexC: return {0.0, 0.0, 1.0};
    case TriangleFeature::EdgeAB: { const double t = along(a, b); return {1.0 - t, t, 0.0}; }
    case TriangleFeature::EdgeBC: { const double t = along(b, c); return {0.0, 1.0 - t, t}; }
    case TriangleFeature::EdgeCA: { const double t = along(c, a); return {t, 0.0, 1.0 - t}; }
    case TriangleFeature::Face: break;
    }
    const glm::dvec3 ab = b - a, ac = c - a, aq = closest.point - a;
    const double d00 = glm::dot(ab, ab), d01 = glm::dot(ab, ac), d11 = glm::dot(ac, ac);
    const double d20 = glm::dot(aq, ab), d21 = glm::dot(aq, ac);
    const double denominator = d00 * d11 - d01 * d01;
    const double wb = (d11 * d20 - d01 * d21) / denominator, wc = (d00 * d21 - d01 * d20) / denominator;
    return {1.0 - wb - wc, wb, wc};
}

double solidAngle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 ra = a - p, rb = b - p, rc = c - p;
    const double la = glm::length(ra), lb = glm::length(rb), lc = glm::length(rc);
    const double det = glm::dot(ra, glm::cross(rb, rc));
    const double denominator = la * lb * lc + glm::dot(ra, rb) * lc + glm::dot(rb, rc) * la + glm::dot(rc, ra) * lb;
    // det > 0 when p is behind the triangle (on the side opposite its normal).
    return 2.0 * std::atan2(det, denominator);
}

} // namespace sdfgen
