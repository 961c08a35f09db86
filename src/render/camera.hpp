#pragma once
#include "sdfgen/mesh.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace sdfgen::render {

// A camera orbiting a target point: yaw about the y axis and pitch above the y = 0 plane (degrees),
// at `distance` from the target, with a vertical field of view of `fovY` degrees.
struct OrbitCamera {
    float yaw = 30.0f;
    float pitch = 20.0f;
    float distance = 3.0f;
    glm::vec3 target{0.0f};
    float fovY = 45.0f;
    float sceneRadius = 1.0f; // size of what is shown, for the clip planes and the pan speed

    glm::vec3 eye() const;
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;

    // Aims at the centre of `bounds` from a distance at which its bounding sphere fills the view
    // (times `zoom`: 2 is twice as far). Keeps yaw and pitch.
    void frame(const WorldBounds& bounds, float zoom = 1.0f);
    // Rotates by degrees; pitch stays within (-89, 89).
    void rotate(float yawDegrees, float pitchDegrees);
    // Moves the target in the view plane by a fraction of the view's height.
    void pan(float dxFraction, float dyFraction);
    // Multiplies the distance by factor^steps (steps > 0 moves closer).
    void zoom(float steps);
};

} // namespace sdfgen::render
