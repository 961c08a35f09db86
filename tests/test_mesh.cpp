// OBJ loading and mesh building: every kind of bad input is an Error naming the file and the
// problem; valid polygons are triangulated, degenerate triangles dropped, normals and bounds right.
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"

#include "support/checks.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <atomic>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

namespace sdfgen {
namespace {

using test::errorFrom;

namespace fs = std::filesystem;

std::string lower(std::string text) {
    for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

class LoadObj : public test::ScratchFolderTest {
protected:

    // Loads `contents` and returns the Error's message, checking that it names the file.
    std::string loadError(const std::string& contents) {
        const std::string path = write("bad.obj", contents);
        const std::string message = errorFrom([&] { loadObj(path); });
        EXPECT_CONTAINS(message, path);
        return message;
    }

};

const char* kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

// ---- Bad input ---------------------------------------------------------------------------------

TEST_F(LoadObj, MissingFileIsAnError) {
    const std::string path = (dir_ / "does-not-exist.obj").string();
    const std::string message = errorFrom([&] { loadObj(path); });
    EXPECT_CONTAINS(message, path);
    EXPECT_CONTAINS(message, "cannot open");
    EXPECT_CONTAINS(message, "No such file");
}

TEST_F(LoadObj, DirectoryIsAnError) {
    const std::string path = dir_.string();
    const std::string message = errorFrom([&] { loadObj(path); });
    EXPECT_CONTAINS(message, path);
    EXPECT_CONTAINS(message, "is a directory");
}

TEST_F(LoadObj, EmptyFileHasNoTriangles) {
    EXPECT_CONTAINS(loadError(""), "no triangles");
}

TEST_F(LoadObj, OnlyPointsAndLinesHaveNoTriangles) {
    const std::string message = loadError(std::string(kTriangle) + "p 1 2 3\nl 1 2\nl 2 3 1\n");
    EXPECT_CONTAINS(message, "no triangles");
}

TEST_F(LoadObj, NanCoordinateIsAnError) {
    const std::string message = loadError("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_CONTAINS(message, ":2:");
    EXPECT_CONTAINS(message, "not a finite number");
}

TEST_F(LoadObj, InfCoordinateIsAnError) {
    const std::string message = loadError("v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n");
    EXPECT_CONTAINS(message, ":3:");
    EXPECT_CONTAINS(message, "not a finite number");
}

TEST_F(LoadObj, OverflowingCoordinateIsAnError) {
    const std::string message = loadError("v 0 0 0\nv 1 0 1e999\nv 0 1 0\nf 1 2 3\n");
    EXPECT_CONTAINS(message, ":2:");
    EXPECT_CONTAINS(message, "not a finite number");
}

TEST_F(LoadObj, CoordinateBeyondFloatRangeIsAnError) {
    // Fine as a double, but infinite once stored as a float.
    const std::string message = loadError("v 0 0 0\nv 1 0 0\nv 0 1 1e39\nf 1 2 3\n");
    EXPECT_CONTAINS(message, ":3:");
    EXPECT_CONTAINS(message, "not a finite number");
}

TEST_F(LoadObj, VertexWithTwoNumbersIsAnError) {
    const std::string message = loadError("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_CONTAINS(message, ":2:");
    EXPECT_CONTAINS(message, "fewer than 3 coordinates");
}

TEST_F(LoadObj, FaceIndexOutOfRangeIsAnError) {
    const std::string message = loadError(std::string(kTriangle) + "f 1 2 9\n");
    EXPECT_CONTAINS(message, "vertex 9");
    EXPECT_CONTAINS(message, "3 vertices");
}

TEST_F(LoadObj, NegativeFaceIndexOutOfRangeIsAnError) {
    // -5 with 3 vertices points before the first vertex.
    const std::string message = loadError(std::string(kTriangle) + "f -1 -2 -5\n");
    EXPECT_CONTAINS(message, "3 vertices");
}

TEST_F(LoadObj, QuadIndexOutOfRangeIsAnError) {
    // tinyobjloader skips a polygon with a bad index with only a warning; the loader must not.
    const std::string message = loadError("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 2 3 9\n");
    EXPECT_CONTAINS(lower(message), "vertex");
}

TEST_F(LoadObj, PolygonIndexOutOfRangeIsAnError) {
    const std::string message =
        loadError("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nf 1 2 3\nf 1 2 3 4 9\n");
    EXPECT_CONTAINS(lower(message), "vertex");
}

TEST_F(LoadObj, FaceIndexZeroIsAnError) {
    const std::string message = loadError(std::string(kTriangle) + "f 0 1 2\n");
    EXPECT_CONTAINS(message, "zero");
}

TEST_F(LoadObj, GarbageTextIsAnError) {
    const std::string message = loadError("Hello, this is not a mesh.\n{ \"json\": true }\n# comment\n");
    EXPECT_CONTAINS(message, "no triangles");
}

TEST_F(LoadObj, BinaryBytesAreAnError) {
    std::string bytes = "\x89PNG\r\n\x1a\n";
    for (int i = 0; i < 512; ++i) bytes += char((i * 37 + 11) % 256);
    bytes[100] = '\0';
    const std::string message = loadError(bytes);
    EXPECT_CONTAINS(message, "no triangles");
}

// ---- Valid input -------------------------------------------------------------------------------

TEST_F(LoadObj, SingleTriangle) {
    const std::string path = write("tri.obj", std::string(kTriangle) + "f 1 2 3\n");
    const Mesh mesh = loadObj(path);
    EXPECT_EQ(mesh.source, path);
    ASSERT_EQ(mesh.triangleCount(), 1u);
    EXPECT_EQ(mesh.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(mesh.faceNormals[0], glm::vec3(0, 0, 1));
    EXPECT_EQ(mesh.droppedDegenerate, 0u);
}

TEST_F(LoadObj, CrLfLineEndingsAndSlashedIndices) {
    const std::string path =
        write("crlf.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nvt 0 0\r\nvn 0 0 1\r\nf 1/1/1 2/1/1 3//1\r\n");
    const Mesh mesh = loadObj(path);
    ASSERT_EQ(mesh.triangleCount(), 1u);
    EXPECT_EQ(mesh.triangles[0], glm::uvec3(0, 1, 2));
}

float totalArea(const Mesh& mesh) {
    double area = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        area += 0.5 * glm::length(glm::cross(mesh.vertex(t, 1) - mesh.vertex(t, 0), mesh.vertex(t, 2) - mesh.vertex(t, 0)));
    }
    return float(area * mesh.unit * mesh.unit); // local to world units
}

TEST_F(LoadObj, QuadBecomesTwoTriangles) {
    const std::string path = write("quad.obj", "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3 4\n");
    const Mesh mesh = loadObj(path);
    ASSERT_EQ(mesh.triangleCount(), 2u);
    EXPECT_FLOAT_EQ(totalArea(mesh), 2.0f);
    for (const glm::vec3& n : mesh.faceNormals) EXPECT_EQ(n, glm::vec3(0, 0, 1)); // winding kept
}

TEST_F(LoadObj, PentagonBecomesThreeTriangles) {
    // A convex pentagon in the z = 1 plane, counter-clockwise seen from +z.
    const std::string path = write("pentagon.obj", "v 0 0 1\nv 2 0 1\nv 3 1 1\nv 1 2 1\nv -1 1 1\nf 1 2 3 4 5\n");
    const Mesh mesh = loadObj(path);
    ASSERT_EQ(mesh.triangleCount(), 3u);
    // Shoelace area of the pentagon: 5.
    EXPECT_FLOAT_EQ(totalArea(mesh), 5.0f);
    for (const glm::vec3& n : mesh.faceNormals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

TEST_F(LoadObj, ConcavePolygonIsTriangulatedInsideItsOutline) {
    // An arrowhead: the corner (2, 1) points inwards, so a plain fan from corner 1 would cover too much.
    const std::string path = write("concave.obj", "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 2 1 0\nv 0 4 0\nf 1 2 3 4 5\n");
    const Mesh mesh = loadObj(path);
    ASSERT_EQ(mesh.triangleCount(), 3u);
    EXPECT_FLOAT_EQ(totalArea(mesh), 10.0f); // shoelace area
    for (const glm::vec3& n : mesh.faceNormals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

TEST_F(LoadObj, DegenerateTrianglesAreDroppedAndCounted) {
    const std::string path = write("degenerate.obj",
                                   "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
                                   "f 1 2 3\n"  // fine
                                   "f 1 2 4\n"  // collinear
                                   "f 1 1 3\n"  // repeated index
                                   "f 3 2 1\n"); // fine (back facing)
    const Mesh mesh = loadObj(path);
    ASSERT_EQ(mesh.triangleCount(), 2u);
    EXPECT_EQ(mesh.droppedDegenerate, 2u);
    EXPECT_EQ(mesh.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(mesh.triangles[1], glm::uvec3(2, 1, 0));
    ASSERT_EQ(mesh.faceNormals.size(), 2u);
    EXPECT_EQ(mesh.faceNormals[0], glm::vec3(0, 0, 1));
    EXPECT_EQ(mesh.faceNormals[1], glm::vec3(0, 0, -1));
}

TEST_F(LoadObj, AllDegenerateHasNoTriangles) {
    const std::string message = loadError("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\nf 1 1 2\nf 3 3 3\n");
    EXPECT_CONTAINS(message, "no triangles");
    EXPECT_CONTAINS(message, "zero area");
}

TEST_F(LoadObj, NegativeIndicesAreRelative) {
    const std::string path = write("relative.obj",
                                   "v 9 9 9\n"
                                   "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"
                                   "v 0 0 1\nf -4 -1 -3\n");
    const Mesh mesh = loadObj(path);
    ASSERT_EQ(mesh.triangleCount(), 2u);
    EXPECT_EQ(mesh.triangles[0], glm::uvec3(1, 2, 3));
    EXPECT_EQ(mesh.triangles[1], glm::uvec3(1, 4, 2));
}

TEST_F(LoadObj, TetrahedronNormalsAreUnitAndOutward) {
    // Counter-clockwise seen from outside.
    const std::string path = write("tetra.obj",
                                   "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                   "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    const Mesh mesh = loadObj(path);
    ASSERT_EQ(mesh.triangleCount(), 4u);
    ASSERT_EQ(mesh.faceNormals.size(), 4u);
    const glm::vec3 centre(mesh.toLocal(glm::dvec3(0.25)));
    for (std::size_t t = 0; t < 4; ++t) {
        const glm::vec3 n = mesh.faceNormals[t];
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f) << "triangle " << t;
        const glm::vec3 faceCentre = (mesh.vertex(t, 0) + mesh.vertex(t, 1) + mesh.vertex(t, 2)) / 3.0f;
        EXPECT_GT(glm::dot(n, faceCentre - centre), 0.0f) << "triangle " << t;
    }
    EXPECT_EQ(mesh.faceNormals[0], glm::vec3(0, 0, -1));
    EXPECT_EQ(mesh.faceNormals[1], glm::vec3(0, -1, 0));
    EXPECT_EQ(mesh.faceNormals[2], glm::vec3(-1, 0, 0));
    const float s = 1.0f / std::sqrt(3.0f);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(mesh.faceNormals[3][a], s, 1e-6f);
}

TEST_F(LoadObj, BoundsCoverUsedVerticesOnly) {
    const std::string path = write("bounds.obj",
                                   "v 100 100 100\n"   // unused
                                   "v -1 2 0.5\nv 3 -4 0.5\nv 0 0 -2\n"
                                   "v -50 -50 -50\n"   // unused
                                   "f 2 3 4\n");
    const Mesh mesh = loadObj(path);
    EXPECT_EQ(mesh.positions.size(), 5u);
    EXPECT_EQ(mesh.worldBounds().min, glm::dvec3(-1, -4, -2));
    EXPECT_EQ(mesh.worldBounds().max, glm::dvec3(3, 2, 0.5));
}

// ---- buildMesh ---------------------------------------------------------------------------------

TEST(BuildMesh, NonFinitePositionIsAnError) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (const glm::vec3 bad : {glm::vec3(nan, 0, 0), glm::vec3(0, inf, 0), glm::vec3(0, 0, -inf)}) {
        const std::string message = errorFrom([&] {
            buildMesh("my-mesh", std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, glm::dvec3(bad)}, {{0, 1, 2}});
        });
        EXPECT_CONTAINS(message, "my-mesh");
        EXPECT_CONTAINS(message, "vertex 4");
        EXPECT_CONTAINS(message, "non-finite");
    }
}

TEST(BuildMesh, IndexOutOfRangeIsAnError) {
    const std::string message = errorFrom([] { buildMesh("my-mesh", std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 3, 1}}); });
    EXPECT_CONTAINS(message, "my-mesh");
    EXPECT_CONTAINS(message, "triangle 2");
    EXPECT_CONTAINS(message, "only 3 vertices");

    const std::string huge = errorFrom([] { buildMesh("m", std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 0xFFFFFFFFu}}); });
    EXPECT_CONTAINS(huge, "only 3 vertices");
}

TEST(BuildMesh, NoTrianglesIsAnError) {
    EXPECT_CONTAINS(errorFrom([] { buildMesh("empty", std::vector<glm::dvec3>{}, {}); }), "no triangles");
    EXPECT_CONTAINS(errorFrom([] { buildMesh("flat", std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}}, {{0, 1, 1}}); }), "zero area");
}

TEST(BuildMesh, ValidMesh) {
    const Mesh mesh = buildMesh("m", std::vector<glm::dvec3>{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {5, 5, 5}, {1, 0, 0}},
                                {{0, 1, 2}, {0, 1, 4}});
    EXPECT_EQ(mesh.source, "m");
    ASSERT_EQ(mesh.triangleCount(), 1u);
    EXPECT_EQ(mesh.droppedDegenerate, 1u);
    EXPECT_EQ(mesh.faceNormals[0], glm::vec3(0, 0, 1));
    // Local coordinates: centred on the box of the used vertices, in units of a power of two.
    EXPECT_EQ(mesh.origin, glm::dvec3(1, 1, 0));
    EXPECT_EQ(mesh.unit, 1.0);
    EXPECT_EQ(mesh.bounds.min, glm::vec3(-1, -1, 0));
    EXPECT_EQ(mesh.bounds.max, glm::vec3(1, 1, 0));
    EXPECT_EQ(mesh.worldBounds().min, glm::dvec3(0, 0, 0));
    EXPECT_EQ(mesh.worldBounds().max, glm::dvec3(2, 2, 0));
    EXPECT_EQ(mesh.positions.size(), 5u);
}

TEST(BuildMesh, ThinTriangleKeepsAccurateNormal) {
    // Nearly degenerate but valid: the normal must still be unit length and exact in direction.
    const Mesh mesh = buildMesh("thin", std::vector<glm::dvec3>{{0, 0, 0}, {1000, 0, 0}, {500, 1e-3f, 0}}, {{0, 1, 2}});
    ASSERT_EQ(mesh.triangleCount(), 1u);
    EXPECT_EQ(mesh.faceNormals[0], glm::vec3(0, 0, 1));
}

} // namespace
} // namespace sdfgen
