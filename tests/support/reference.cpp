#include "support/reference.hpp"
#include "core/accel/bvh.hpp"
#include "support/checks.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace sdfgen::test {

MeshCheck checkMesh(const Mesh& mesh) {
    const Bvh tree(mesh);
    return MeshTopology(mesh).check(mesh, tree);
}

BakeResult bakeWith(const Mesh& mesh, int res, DistanceMethod method, SignMethod sign, int threads, int rays) {
    BakeSettings settings;
    settings.res = res;
    settings.method = method;
    settings.sign = sign;
    settings.rays = rays;
    return test::bakeMesh(mesh, settings, threads);
}

const Field& bruteField(const std::string& name, const Mesh& mesh, int res) {
    static std::map<std::string, Field> cache;
    const std::string key = name + "@" + std::to_string(res);
    auto it = cache.find(key);
    if (it == cache.end()) {
        it = cache.emplace(key, bakeWith(mesh, res, DistanceMethod::Brute, SignMethod::Winding).field.dense()).first;
    }
    return it->second;
}

SignCounts countSigns(const Field& test, const Field& reference) {
    SignCounts c;
    const double voxel = reference.grid.voxel;
    for (std::size_t i = 0; i < reference.values.size(); ++i) {
        const float a = test.values[i], b = reference.values[i];
        const bool wrong = (a < 0) != (b < 0);
        c.referenceInside += b < 0;
        if (std::min(std::fabs(a), std::fabs(b)) < voxel) {
            ++c.near;
            c.nearWrong += wrong;
        } else {
            ++c.far;
            c.farWrong += wrong;
        }
    }
    return c;
}

} // namespace sdfgen::test
