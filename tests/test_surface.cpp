// `sdfgen surface`: the iso-surface of the exact, robustly signed field of a broken mesh (a hole,
// overlapping shells, an open cup, flipped faces) is a closed, manifold, consistently oriented
// mesh by sdfgen's own mesh check, facing outwards, and it stays within a voxel of the input (or
// of the patches that close its openings).
#include "core/mesh/geometry.hpp"
#include "sdfgen/surface.hpp"
#include "core/accel/topology.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"

#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace sdfgen {
namespace {

using test::errorFrom;

Mesh merged(const std::string& name, const std::vector<Mesh>& parts) {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    for (const Mesh& part : parts) {
        const auto base = unsigned(positions.size());
        positions.insert(positions.end(), part.positions.begin(), part.positions.end());
        for (const glm::uvec3& t : part.triangles) triangles.push_back(t + glm::uvec3(base));
    }
    return buildMesh(name, positions, triangles);
}

Mesh sphereWithAHole() {
    const Mesh sphere = test::icosphere(1.0f, 3);
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
        const glm::vec3 centroid = (sphere.vertex(t, 0) + sphere.vertex(t, 1) + sphere.vertex(t, 2)) / 3.0f;
        if (centroid.y < 0.9f) kept.push_back(sphere.triangles[t]); // a cap at the top goes
    }
    return buildMesh("sphere with a hole", sphere.positions, kept);
}

Mesh overlappingShells() {
    const Mesh sphere = test::icosphere(0.8f, 3);
    Mesh left = sphere, right = sphere;
    for (glm::vec3& p : left.positions) p.x -= 0.4f;
    for (glm::vec3& p : right.positions) p.x += 0.4f;
    return merged("two overlapping shells", {left, right});
}

Mesh flippedFaces() {
    Mesh sphere = test::icosphere(1.0f, 3);
    for (std::size_t t = 0; t < sphere.triangles.size(); t += 7) std::swap(sphere.triangles[t].y, sphere.triangles[t].z);
    return buildMesh("sphere with flipped faces", sphere.positions, sphere.triangles);
}

// A cone-shaped cup open at its rim (a circle of radius 1 in the y = 0 plane, apex at y = -1.5).
Mesh openCup() {
    const int n = 48;
    std::vector<glm::vec3> positions = {{0.0f, -1.5f, 0.0f}};
    std::vector<glm::uvec3> triangles;
    for (int k = 0; k < n; ++k) {
        const double a = 2.0 * M_PI * k / n;
        positions.emplace_back(float(std::cos(a)), 0.0f, float(std::sin(a)));
        triangles.emplace_back(0u, unsigned(1 + k), unsigned(1 + (k + 1) % n)); // normals out of the cup
    }
    return buildMesh("open cup", positions, triangles);
}

// Fans from each boundary loop's centroid to its edges: where the winding number's surface closes
// the openings (3 corners per triangle).
std::vector<glm::dvec3> closingFans(const Mesh& mesh) {
    const MeshTopology topology(mesh);
    std::vector<glm::dvec3> fans;
    for (const std::vector<std::uint32_t>& loop : topology.boundaryLoops()) {
        glm::dvec3 centre(0.0);
        for (const std::uint32_t v : loop) centre += topology.position(v);
        centre /= double(loop.size());
        for (std::size_t i = 0; i < loop.size(); ++i) {
            fans.insert(fans.end(), {centre, topology.position(loop[i]), topology.position(loop[(i + 1) % loop.size()])});
        }
    }
    return fans;
}

double distanceToTriangles(const glm::dvec3& p, const Mesh& mesh, const std::vector<glm::dvec3>& extra) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const ClosestPoint c = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
        best = std::min(best, glm::distance(p, c.point));
    }
    for (std::size_t t = 0; t + 2 < extra.size(); t += 3) {
        best = std::min(best, glm::distance(p, closestPointOnTriangle(p, extra[t], extra[t + 1], extra[t + 2]).point));
    }
    return best;
}

double signedVolume(const Mesh& mesh) {
    double volume = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        volume += glm::dot(glm::dvec3(mesh.vertex(t, 0)), glm::cross(glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)))) / 6.0;
    }
    return volume;
}

// Iso-surfaces are extracted by the OpenVDB plug-in, and PLY read back by the Assimp one: skipped
// in a build without them.
class Surface : public test::ScratchFolderTest {
protected:
    void SetUp() override {
        if (!SDFGEN_HAS_OPENVDB || !SDFGEN_HAS_ASSIMP) GTEST_SKIP() << "built without OpenVDB or Assimp";
        ScratchFolderTest::SetUp();
    }
};

TEST_F(Surface, BrokenMeshesGiveClosedManifoldSurfacesNearTheInput) {
    for (const Mesh& input : {sphereWithAHole(), overlappingShells(), flippedFaces(), openCup()}) {
        SCOPED_TRACE(input.source);
        EXPECT_FALSE(MeshTopology(input).check(input, Bvh(input)).closedAndClean()) << "the input is broken";
        // Within a voxel of the input, or of the patches that close its holes. Voxels larger than
        // the triangles: next to a flipped face the winding number's surface dents inwards by
        // about a third of the face's size.
        const std::vector<glm::dvec3> closing = closingFans(input);
        BakeSettings settings;
        settings.res = 24;
        const Field field = test::bakeMesh(input, settings).field.dense();
        for (const double adaptivity : {0.0, 0.5}) {
            SCOPED_TRACE(adaptivity);
            const SurfaceMesh surface = extractSurface(field, 0.0, adaptivity);
            const Mesh output = buildMesh("surface", surface.positions, surface.triangles);
            EXPECT_EQ(output.droppedDegenerate, 0u);
            const MeshCheck check = MeshTopology(output).check(output, Bvh(output));
            EXPECT_EQ(check.boundaryEdges, 0u);
            EXPECT_EQ(check.nonManifoldEdges, 0u);
            EXPECT_EQ(check.inconsistentEdges, 0u);
            EXPECT_EQ(check.nonManifoldVertices, 0u);
            EXPECT_GT(signedVolume(output), 0.0) << "triangles face outwards";
            const double h = field.grid.voxel;
            double farthest = 0;
            // Measured in the input's local coordinates (where its triangles and fans are), in world units.
            for (const glm::dvec3& p : output.worldPositions()) {
                farthest = std::max(farthest, distanceToTriangles(input.toLocal(p), input, closing) * input.unit);
            }
            EXPECT_LE(farthest, h) << "farthest output vertex from the input, voxel " << h;
        }
    }
}

TEST_F(Surface, OffsetSurfaceIsAtTheIsoDistance) {
    const Mesh sphere = test::icosphere(1.0f, 3);
    BakeSettings settings;
    settings.res = 32;
    settings.padding = 0.3f;
    const Field field = test::bakeMesh(sphere, settings).field.dense();
    const double iso = 0.2;
    const SurfaceMesh surface = extractSurface(field, iso, 0.0);
    const double sag = test::icosphereSag(1.0f, 3);
    for (const glm::vec3& p : surface.positions) {
        EXPECT_NEAR(glm::length(glm::dvec3(p)), 1.0 + iso, 0.25 * field.grid.voxel + sag);
    }
}

TEST_F(Surface, VerticesBeyondSinglePrecisionAreRefused) {
    BakeSettings settings;
    settings.res = 12;
    Field field = test::bakeMesh(test::icosphere(1.0f, 2), settings).field.dense();
    field.grid.voxel = 1e300; // the vertices' float positions overflow: no mesh file can hold them
    EXPECT_CONTAINS(errorFrom([&] { extractSurface(field, 0.0, 0.0); }), "the surface's vertices are beyond single precision");
    field.grid.voxel = 1.0;
    field.grid.origin = glm::dvec3(1.7e308, 0.0, 0.0);
    EXPECT_CONTAINS(errorFrom([&] { extractSurface(field, 0.0, 0.0); }), "beyond single precision (grid origin 1.7e+308 0 0");
}

TEST_F(Surface, SurfaceReachingTheBoundaryIsRefused) {
    BakeSettings settings;
    settings.res = 16;
    settings.padding = 0.0f;
    const Field field = test::bakeMesh(test::box({1, 1, 1}), settings).field.dense();
    EXPECT_CONTAINS(errorFrom([&] { extractSurface(field, 0.5 * field.grid.voxel, 0.0); }), "padding");
    EXPECT_CONTAINS(errorFrom([&] { extractSurface(field, 0.0, 2.0); }), "adaptivity");
}

TEST_F(Surface, ObjAndPlyReadBackAsTheSameMesh) {
    BakeSettings settings;
    settings.res = 16;
    const SurfaceMesh surface = extractSurface(test::bakeMesh(test::icosphere(1.0f, 2), settings).field.dense(), 0.0, 0.0);
    for (const std::string name : {"surface.obj", "surface.ply"}) {
        SCOPED_TRACE(name);
        const std::string path = (dir_ / name).string();
        saveSurface(surface, path);
        const Mesh loaded = loadMesh(path);
        ASSERT_EQ(loaded.triangleCount(), surface.triangles.size());
        for (std::size_t t = 0; t < surface.triangles.size(); t += 97) {
            for (int c = 0; c < 3; ++c) EXPECT_EQ(loaded.vertex(t, c), surface.positions[surface.triangles[t][c]]);
        }
    }
    EXPECT_CONTAINS(errorFrom([&] { saveSurface(surface, (dir_ / "surface.stl").string()); }), ".obj, .ply");
}

} // namespace
} // namespace sdfgen
