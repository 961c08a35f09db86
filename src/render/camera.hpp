#pragma once
#include "sdfgen/mesh.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace sdfgen::render {

// A camera orbiting a target point: yaw about the y axis (-180..180) and pitch above the
// horizontal (degrees), at `distance` from the target, with a vertical field of view of `fovY`
// degrees, or orthographic with the view height the perspective one has at the target.
struct OrbitCamera {
    float yaw = 30.0f;
    float pitch = 20.0f;
    float distance = 3.0f;
    glm::vec3 target{0.0f};
    float fovY = 45.0f;
    bool orthographic = false;
    float sceneRadius = 1.0f; // size of what is shown, for the clip planes and the pan speed
    // Horizontal shift of the image in normalized device coordinates: the target appears at
    // x = offsetX (e.g. the centre of the part of a window that a panel leaves free).
    float offsetX = 0.0f;

    glm::vec3 eye() const;
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;
    float viewHeight() const; // of the view at the target, world units

    // Aims at the centre of `bounds` from a distance at which its bounding sphere fills the view
    // (times `zoom`: 2 is twice as far), also across when the view is narrower than tall
    // (`aspect` = width / height). Keeps yaw and pitch.
    void frame(const WorldBounds& bounds, float zoom = 1.0f, float aspect = 1.0f);
    // The view's aspect changed from `before` to `after` (a resized window): moves the camera so
    // that the view keeps its extent across its narrower side, as frame() fits it, and what was
    // framed stays framed at the same size.
    void keepFraming(float before, float after);
    // Rotates by degrees; yaw wraps to -180..180, pitch stays within (-89, 89).
    void rotate(float yawDegrees, float pitchDegrees);
    // Moves the target in the view plane by a fraction of the view's height.
    void pan(float dxFraction, float dyFraction);
    // Multiplies the distance by factor^steps (steps > 0 moves closer).
    void zoom(float steps);
};

} // namespace sdfgen::render
