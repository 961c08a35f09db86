#pragma once
#include "core/field.hpp"
#include "core/kdtree.hpp"
#include "core/mesh.hpp"
#include "core/parallel.hpp"
#include "core/topology.hpp"

#include <string>

namespace sdfgen {

// How distances are measured.
enum class DistanceMethod {
    Rays,  // the original report's ray sampling: an upper bound, see generateRayField
    Exact, // the true distance to the nearest triangle (computeNearest)
    Brute, // every triangle for every sample in double, signs from the exact winding number: the reference
};
// How inside is told from outside.
enum class SignMethod {
    Default,      // Rays for the rays method, Auto otherwise
    Auto,         // Pseudonormal where the mesh check proves it right, Winding otherwise
    Rays,         // majority of back-face first hits (rays per sample from BakeSettings::rays)
    Pseudonormal, // angle-weighted pseudonormal of the closest feature
    Winding,      // generalized winding number > 1/2
};
const char* toString(DistanceMethod method);
const char* toString(SignMethod sign);

// What to bake: the grid (see makeGrid), the method and the sign.
struct BakeSettings {
    int res = 64;
    float padding = 0.1f;
    DistanceMethod method = DistanceMethod::Exact;
    SignMethod sign = SignMethod::Default;
    int rays = 64; // for the rays method and the rays sign
};

// A bake's field and what was decided on the way.
struct BakeResult {
    Field field;
    SignMethod sign = SignMethod::Default; // the sign method actually used
    bool checked = false;                  // whether the mesh check ran (sign auto)
    MeshCheck check;
    std::string signReason; // why auto chose as it did, for the summary and panel
    double distanceSeconds = 0; // time spent on distances (and on rays, when the sign needs them)
    double signSeconds = 0;     // time spent on the mesh check and the sign
};

// The ray-sampling generator. For each sample, `rays` rays leave in the directions of
// sphereDirections(rays); the distance is the nearest hit of any ray (an upper bound of the true
// distance), and the sample is inside (negative) when more than half of the rays that hit anything
// first hit a back face. A sample whose rays all miss lies outside, and gets the distance to the
// farthest corner of the mesh's bounding box: finite, positive and still an upper bound.
// The result does not depend on the thread count.
Field generateRayField(const Mesh& mesh, const KdTree& tree, const Grid& grid, int rays, const RunControl& control);

// Grid + distances + signs + the field's recorded method line, in one call; the method line reads
// e.g. "exact sign=auto/winding res=128 padding=0.1". Throws Error for bad settings.
BakeResult bake(const Mesh& mesh, const KdTree& tree, const BakeSettings& settings, const RunControl& control);

} // namespace sdfgen
