#include "render/camera.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <algorithm>
#include <cmath>

namespace sdfgen::render {

glm::vec3 OrbitCamera::eye() const {
    const float y = glm::radians(yaw), p = glm::radians(pitch);
    return target + distance * glm::vec3(std::cos(p) * std::sin(y), std::sin(p), std::cos(p) * std::cos(y));
}

glm::mat4 OrbitCamera::view() const { return glm::lookAt(eye(), target, glm::vec3(0, 1, 0)); }

float OrbitCamera::viewHeight() const { return 2.0f * distance * std::tan(glm::radians(0.5f * fovY)); }

glm::mat4 OrbitCamera::projection(float aspect) const {
    const float farPlane = distance + 50.0f * sceneRadius;
    const glm::mat4 shift = glm::translate(glm::mat4(1.0f), glm::vec3(offsetX, 0.0f, 0.0f));
    if (orthographic) {
        const float h = 0.5f * viewHeight();
        return shift * glm::ortho(-h * aspect, h * aspect, -h, h, distance - 4.0f * sceneRadius, farPlane);
    }
    const float nearPlane = std::max(distance - 4.0f * sceneRadius, distance * 0.01f);
    return shift * glm::perspective(glm::radians(fovY), aspect, nearPlane, farPlane);
}

namespace {
// How much farther frame() moves the camera for a view of `aspect` (width / height): nothing for
// a wide view, enough for the scene to fit across a narrow one.
float narrowness(float aspect) { return 1.0f / std::clamp(aspect, 0.2f, 1.0f); }
} // namespace

void OrbitCamera::frame(const WorldBounds& bounds, float zoomFactor, float aspect) {
    target = glm::vec3(0.5 * (bounds.min + bounds.max));
    sceneRadius = std::max(float(0.5 * glm::length(bounds.extent())), 1e-6f);
    distance = zoomFactor * sceneRadius / std::sin(glm::radians(0.5f * fovY)) * 1.05f * narrowness(aspect);
}

void OrbitCamera::keepFraming(float before, float after) {
    if (!(before > 0.0f && after > 0.0f)) return;
    distance *= narrowness(after) / narrowness(before);
}

void OrbitCamera::rotate(float yawDegrees, float pitchDegrees) {
    yaw += yawDegrees;
    yaw -= 360.0f * std::floor((yaw + 180.0f) / 360.0f);
    pitch = std::clamp(pitch + pitchDegrees, -89.0f, 89.0f);
}

void OrbitCamera::pan(float dxFraction, float dyFraction) {
    const glm::mat4 v = view();
    const glm::vec3 right(v[0][0], v[1][0], v[2][0]);
    const glm::vec3 up(v[0][1], v[1][1], v[2][1]);
    target += (-dxFraction * right + dyFraction * up) * viewHeight();
}

void OrbitCamera::zoom(float steps) { distance = std::max(distance * std::pow(0.9f, steps), 1e-4f); }

} // namespace sdfgen::render
