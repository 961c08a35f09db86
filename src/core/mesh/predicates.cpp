#include "core/mesh/predicates.hpp"

#include <glm/vec2.hpp>
#include <algorithm>
#include <cfloat>
#include <cmath>

namespace sdfgen {

namespace {

static_assert(FLT_EVAL_METHOD == 0, "the error-free sums need double arithmetic without extended precision");

// s + e == a + b exactly, with s the rounded sum (Knuth's two-sum: no ordering of a and b needed).
inline void twoSum(double a, double b, double& s, double& e) {
    s = a + b;
    const double bRounded = s - a;
    const double aRounded = s - bRounded;
    e = (a - aRounded) + (b - bRounded);
}

// An exact sum of doubles, kept as a nonoverlapping expansion: components in increasing magnitude,
// zeros dropped, each smaller than half an ulp of the next. Adding a value runs two-sum up the
// components, which keeps that form, and the largest (last) component carries the sum's sign.
class ExactSum {
public:
    void add(double x) {
        if (x == 0.0) return;
        int kept = 0;
        for (int i = 0; i < count_; ++i) {
            double sum, error;
            twoSum(x, parts_[i], sum, error);
            if (error != 0.0) parts_[kept++] = error;
            x = sum;
        }
        if (x != 0.0) parts_[kept++] = x;
        count_ = kept;
    }
    int sign() const { return count_ == 0 ? 0 : parts_[count_ - 1] > 0.0 ? 1 : -1; }

private:
    // orient3dExact adds 48 values (orient2d 6), and each addition grows the expansion by at most
    // one component.
    double parts_[48];
    int count_ = 0;
};

// Adds sign * det(p, q, r) = sign * p · (q × r) as its six monomials, each exactly two doubles: the
// product of two floats is exact in double (48 bits), and fma gives the rounding error of the
// third factor. Finite floats keep every term clear of double overflow and underflow.
void addDeterminant(ExactSum& sum, const glm::vec3& p, const glm::vec3& q, const glm::vec3& r, double sign) {
    const auto addMonomial = [&](float x, float y, float z, double s) {
        const double xy = double(x) * double(y);
        const double high = xy * double(z);
        const double low = std::fma(xy, double(z), -high);
        sum.add(s * high);
        sum.add(s * low);
    };
    addMonomial(p.x, q.y, r.z, sign);
    addMonomial(p.x, q.z, r.y, -sign);
    addMonomial(p.y, q.z, r.x, sign);
    addMonomial(p.y, q.x, r.z, -sign);
    addMonomial(p.z, q.x, r.y, sign);
    addMonomial(p.z, q.y, r.x, -sign);
}

// The sign of (b - a) × (c - a) in 2D, exactly. In double first: each of the two products passes
// through 4 roundings, so as for orient3d below (4 + 128u) u times the computed sum of their
// magnitudes bounds the error. Otherwise det(b, c) - det(a, c) + det(a, b), six products of two
// floats, each exact in double, summed exactly.
int orient2d(const glm::vec2& a, const glm::vec2& b, const glm::vec2& c) {
    const double left = (double(b.x) - a.x) * (double(c.y) - a.y), right = (double(b.y) - a.y) * (double(c.x) - a.x);
    const double area = left - right;
    constexpr double u = DBL_EPSILON / 2;
    const double bound = (4.0 + 128.0 * u) * u * (std::fabs(left) + std::fabs(right));
    if (area > bound) return 1;
    if (area < -bound) return -1;
    ExactSum sum;
    sum.add(double(b.x) * double(c.y));
    sum.add(-double(b.y) * double(c.x));
    sum.add(-double(a.x) * double(c.y));
    sum.add(double(a.y) * double(c.x));
    sum.add(double(a.x) * double(b.y));
    sum.add(-double(a.y) * double(b.x));
    return sum.sign();
}

// Whether closed segments pq and ab have a point in common.
bool segmentsMeet2d(const glm::vec2& p, const glm::vec2& q, const glm::vec2& a, const glm::vec2& b) {
    const int pqa = orient2d(p, q, a), pqb = orient2d(p, q, b), abp = orient2d(a, b, p), abq = orient2d(a, b, q);
    if (pqa == 0 && pqb == 0 && abp == 0 && abq == 0) {
        // On one line: the segments meet when their extents overlap on both axes.
        return std::max(std::min(p.x, q.x), std::min(a.x, b.x)) <= std::min(std::max(p.x, q.x), std::max(a.x, b.x)) &&
               std::max(std::min(p.y, q.y), std::min(a.y, b.y)) <= std::min(std::max(p.y, q.y), std::max(a.y, b.y));
    }
    return pqa * pqb <= 0 && abp * abq <= 0;
}

// Whether the closed segment pq meets the closed triangle abc, which has area.
bool segmentMeetsTriangle2d(const glm::vec2& p, const glm::vec2& q, const glm::vec2& a, const glm::vec2& b,
                            const glm::vec2& c) {
    const auto inside = [&](const glm::vec2& x) {
        const int s1 = orient2d(a, b, x), s2 = orient2d(b, c, x), s3 = orient2d(c, a, x);
        return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
    };
    return inside(p) || inside(q) || segmentsMeet2d(p, q, a, b) || segmentsMeet2d(p, q, b, c) || segmentsMeet2d(p, q, c, a);
}

} // namespace

int orient3dExact(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
    // The determinant is multilinear in its rows, and terms with a twice vanish:
    // det(b - a, c - a, d - a) = det(b, c, d) - det(a, c, d) + det(a, b, d) - det(a, b, c).
    ExactSum sum;
    addDeterminant(sum, b, c, d, 1.0);
    addDeterminant(sum, a, c, d, -1.0);
    addDeterminant(sum, a, b, d, 1.0);
    addDeterminant(sum, a, b, c, -1.0);
    return sum.sign();
}

int orient3d(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
    const double bx = double(b.x) - a.x, by = double(b.y) - a.y, bz = double(b.z) - a.z;
    const double cx = double(c.x) - a.x, cy = double(c.y) - a.y, cz = double(c.z) - a.z;
    const double dx = double(d.x) - a.x, dy = double(d.y) - a.y, dz = double(d.z) - a.z;
    const double byCz = by * cz, bzCy = bz * cy, bzCx = bz * cx, bxCz = bx * cz, bxCy = bx * cy, byCx = by * cx;
    const double volume = dx * (byCz - bzCy) + dy * (bzCx - bxCz) + dz * (bxCy - byCx);
    const double permanent = std::fabs(dx) * (std::fabs(byCz) + std::fabs(bzCy)) +
                             std::fabs(dy) * (std::fabs(bzCx) + std::fabs(bxCz)) +
                             std::fabs(dz) * (std::fabs(bxCy) + std::fabs(byCx));
    // Each of the six monomials (dx by cz, ...) passes through at most 8 roundings (three
    // differences, two products, the minor's difference, two sums), so with u = 2^-53 the computed
    // volume is within 8u / (1 - 8u) of the sum of the monomials' magnitudes, which the computed
    // permanent underestimates by at most the same factor; (8 + 256u) u covers both and the rounding
    // of the product below. Float inputs cannot underflow or overflow here, and fused multiply-adds
    // only remove roundings.
    constexpr double u = DBL_EPSILON / 2;
    const double bound = (8.0 + 256.0 * u) * u * permanent;
    if (volume > bound) return 1;
    if (volume < -bound) return -1;
    // A zero permanent means a zero difference in every monomial (differences of floats are exact
    // when they round to zero), as for points on an axis-aligned plane: the volume is exactly 0.
    if (permanent == 0.0) return 0;
    // Nearby points (nearly coplanar neighbours, as subdivided meshes have by the million) usually
    // have exact differences whose pairwise products are exact too: then each monomial x·y·z is
    // exactly two doubles (fma gives the rounding error of the last product), and the six of them,
    // twelve terms, are summed exactly, a quarter of orient3dExact's 48.
    bool exact = true;
    const auto difference = [&](float q, float p) {
        double s, e;
        twoSum(double(q), -double(p), s, e);
        exact = exact && e == 0.0;
        return s;
    };
    const double ex[3] = {difference(b.x, a.x), difference(b.y, a.y), difference(b.z, a.z)};
    const double ey[3] = {difference(c.x, a.x), difference(c.y, a.y), difference(c.z, a.z)};
    const double ez[3] = {difference(d.x, a.x), difference(d.y, a.y), difference(d.z, a.z)};
    if (!exact) return orient3dExact(a, b, c, d);
    // det(b - a, c - a, d - a) = Σ over the permutations (i, j, k) of sign · ex[i] ey[j] ez[k].
    constexpr int kPermutations[6][4] = {{0, 1, 2, 1}, {0, 2, 1, -1}, {1, 2, 0, 1}, {1, 0, 2, -1}, {2, 0, 1, 1}, {2, 1, 0, -1}};
    ExactSum sum;
    for (const auto& [i, j, k, sign] : kPermutations) {
        const double xy = ex[i] * ey[j];
        if (std::fma(ex[i], ey[j], -xy) != 0.0) return orient3dExact(a, b, c, d);
        const double high = xy * ez[k];
        sum.add(sign * high);
        sum.add(sign * std::fma(xy, ez[k], -high));
    }
    return sum.sign();
}

bool segmentMeetsTriangle(const glm::vec3& p, const glm::vec3& q, const glm::vec3& a, const glm::vec3& b,
                          const glm::vec3& c) {
    const int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
    if (sp == sq && sp != 0) return false; // both ends strictly on one side
    if (sp != 0 || sq != 0) {
        // The line pq meets the plane in one point, inside the closed triangle when the line passes
        // on one side of, or through, each of the three edges, the same side for all.
        const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
        return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
    }
    // All in one plane: drop an axis along which the triangle keeps its area (projecting then keeps
    // every incidence) and decide in 2D.
    for (int drop = 0; drop < 3; ++drop) {
        const auto project = [drop](const glm::vec3& v) { return glm::vec2(v[(drop + 1) % 3], v[(drop + 2) % 3]); };
        if (orient2d(project(a), project(b), project(c)) != 0) {
            return segmentMeetsTriangle2d(project(p), project(q), project(a), project(b), project(c));
        }
    }
    return false;
}

} // namespace sdfgen
