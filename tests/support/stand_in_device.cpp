#include "support/stand_in_device.hpp"
#include "core/distance/exact.hpp"
#include "core/mesh/geometry.hpp"
#include "core/mesh/sample_positions.hpp"

#include <cmath>
#include <memory>

namespace sdfgen::test {

void StandInDevice::nearest(const Mesh& mesh, const Grid& grid, const PseudonormalSign* sign, const RunControl& control,
                            std::vector<float>& distance) {
    if (calls_) ++*calls_;
    NearestField field = computeNearest(mesh, Bvh(mesh), grid, control);
    distance = std::move(field.distance);
    if (!sign) return;
    for (int k = 0; k < grid.dims.z; ++k) {
        for (int j = 0; j < grid.dims.y; ++j) {
            for (int i = 0; i < grid.dims.x; ++i) {
                const std::size_t index = grid.index(i, j, k);
                const std::uint32_t t = field.triangle[index];
                const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
                const ClosestPoint q = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                              glm::dvec3(mesh.vertex(t, 2)));
                const bool inside = (glm::dot(p - q.point, sign->normals[7 * t + int(q.feature)]) < 0.0) != sign->flipped;
                if (inside) distance[index] = -distance[index];
                if (index % 3 == 0) distance[index] = std::nanf("");
            }
        }
    }
}
std::vector<std::int32_t> StandInDevice::windingNumbers(const Mesh& mesh, const std::vector<glm::dvec3>& corners,
                                                        const std::vector<std::int32_t>& weights, const WindingFans* fans, const Grid& grid,
                                                        const RunControl&, std::vector<std::uint8_t>& sides) {
    if (calls_) ++*calls_;
    std::vector<std::int32_t> out(grid.sampleCount());
    if (fans) sides.assign(grid.sampleCount(), 2);
    for (int k = 0; k < grid.dims.z; ++k) {
        for (int j = 0; j < grid.dims.y; ++j) {
            for (int i = 0; i < grid.dims.x; ++i) {
                const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
                double sum = 0;
                for (std::size_t t = 0; 3 * t + 2 < corners.size(); ++t) {
                    sum += weights[t] * solidAngle(p, corners[3 * t], corners[3 * t + 1], corners[3 * t + 2]);
                }
                const std::size_t index = grid.index(i, j, k);
                out[index] = std::int32_t(std::lround(sum / (4.0 * M_PI)));
                if (!fans || index % 2 == 0) continue;
                double w = out[index];
                for (const WindingFans::Fan& fan : fans->fans) {
                    const glm::dvec3& centre = fans->points[fan.first];
                    for (std::uint32_t v = 0; v < fan.count; ++v) {
                        const glm::dvec3& a = fans->points[fan.first + 1 + (v + 1) % fan.count];
                        const glm::dvec3& b = fans->points[fan.first + 1 + v];
                        w -= fan.weight * solidAngle(p, a, b, centre) / (4.0 * M_PI);
                    }
                }
                sides[index] = std::fabs(w) > 0.5;
            }
        }
    }
    return out;
}

ComputeDevicePlugin standInDevice(const char* name, bool hardware, int* calls) {
    ComputeDevicePlugin plugin;
    plugin.name = name;
    plugin.description = "the CPU standing in for a device";
    plugin.driver = "stand-in driver";
    plugin.open = [hardware, calls]() -> std::unique_ptr<ComputeDevice> { return std::make_unique<StandInDevice>(hardware, calls); };
    return plugin;
}

} // namespace sdfgen::test
