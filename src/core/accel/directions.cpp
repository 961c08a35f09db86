#include "core/accel/directions.hpp"

#include <cmath>

namespace sdfgen {

std::vector<glm::vec3> sphereDirections(int count) {
    std::vector<glm::vec3> directions;
    directions.reserve(std::size_t(count));
    const double goldenAngle = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        // z at the centre of the i-th of `count` equal-area bands, so z is uniform on [-1, 1].
        const double z = 1.0 - (2.0 * i + 1.0) / count;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = goldenAngle * i;
        directions.emplace_back(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
    }
    return directions;
}

} // namespace sdfgen
