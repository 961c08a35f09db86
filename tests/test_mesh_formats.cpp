// Mesh input beyond OBJ: the same triangles written by Assimp's exporter (Debian's assimp-utils)
// as STL (ASCII and binary), PLY (ASCII and binary), glTF, GLB and ASCII FBX (Assimp 5.2 cannot
// read back its own binary FBX export), and by hand as OFF, load
// into the same mesh and bake into the same field as the OBJ; node transforms and instancing are
// applied; bad files get one-line errors.
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"

#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace sdfgen {
namespace {

using test::errorFrom;

// An icosphere with vertices rounded to multiples of 1/64, which every text format writes and
// reads back exactly, so that any difference between the fields comes from the loader.
Mesh roundedSphere() {
    Mesh sphere = test::icosphere(0.9f, 2);
    for (glm::vec3& p : sphere.positions) p = glm::round(p * 64.0f) / 64.0f;
    return buildMesh("rounded sphere", sphere.positions, sphere.triangles);
}

std::string objText(const Mesh& mesh) {
    std::string text;
    char line[128];
    for (const glm::vec3& p : mesh.positions) {
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z));
        text += line;
    }
    for (const glm::uvec3& t : mesh.triangles) text += "f " + std::to_string(t.x + 1) + " " + std::to_string(t.y + 1) + " " + std::to_string(t.z + 1) + "\n";
    return text;
}

std::string offText(const Mesh& mesh) {
    std::string text = "OFF\n" + std::to_string(mesh.positions.size()) + " " + std::to_string(mesh.triangles.size()) + " 0\n";
    char line[128];
    for (const glm::vec3& p : mesh.positions) {
        std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z));
        text += line;
    }
    for (const glm::uvec3& t : mesh.triangles) text += "3 " + std::to_string(t.x) + " " + std::to_string(t.y) + " " + std::to_string(t.z) + "\n";
    return text;
}

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t n = std::uint32_t(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) n |= std::uint8_t(bytes[i + 2]);
        out += digits[(n >> 18) & 63];
        out += digits[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[n & 63] : '=';
    }
    return out;
}

// The files are made by Assimp's own exporter (assimp-utils) and some are read through the Assimp
// plug-in: skipped in a build without it.
class MeshFormats : public test::ScratchFolderTest {
protected:
    void SetUp() override {
        if (!SDFGEN_HAS_ASSIMP) GTEST_SKIP() << "built without Assimp (SDFGEN_ASSIMP=OFF)";
        ScratchFolderTest::SetUp();
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    // Runs Debian's `assimp export` on `input`; false when assimp-utils is not installed.
    bool assimpExport(const std::string& input, const std::string& output, const std::string& format) {
        const std::string command = "assimp export '" + input + "' '" + output + "' -f" + format + " > /dev/null 2>&1";
        const int status = std::system(command.c_str());
        return status == 0;
    }
};

TEST_F(MeshFormats, EveryFormatGivesTheObjsField) {
    if (std::system("command -v assimp > /dev/null 2>&1") != 0) GTEST_SKIP() << "assimp (assimp-utils) is not installed";
    const Mesh sphere = roundedSphere();
    const std::string obj = write("sphere.obj", objText(sphere));
    const Mesh fromObj = loadMesh(obj);
    BakeSettings settings;
    settings.res = 16;
    const Field reference = test::bakeMesh(fromObj, settings).field.dense();

    std::vector<std::string> files = {write("sphere.off", offText(sphere))};
    const std::vector<std::pair<std::string, std::string>> exports = {
        {"stl", "ascii.stl"}, {"stlb", "binary.stl"}, {"ply", "ascii.ply"}, {"plyb", "binary.ply"},
        {"gltf2", "sphere.gltf"}, {"glb2", "sphere.glb"}, {"fbxa", "sphere.fbx"}};
    for (const auto& [format, name] : exports) {
        ASSERT_TRUE(assimpExport(obj, path(name), format)) << "assimp export -f" << format;
        files.push_back(path(name));
    }
    for (const std::string& file : files) {
        SCOPED_TRACE(file);
        const Mesh mesh = loadMesh(file);
        EXPECT_EQ(mesh.triangleCount(), fromObj.triangleCount());
        EXPECT_EQ(mesh.droppedDegenerate, 0u);
        EXPECT_EQ(mesh.bounds.min, fromObj.bounds.min);
        EXPECT_EQ(mesh.bounds.max, fromObj.bounds.max);
        const Field field = test::bakeMesh(mesh, settings).field.dense();
        ASSERT_EQ(field.grid.dims, reference.grid.dims);
        ASSERT_EQ(field.values.size(), reference.values.size());
        std::size_t different = 0;
        for (std::size_t i = 0; i < field.values.size(); ++i) different += field.values[i] != reference.values[i];
        EXPECT_EQ(different, 0u) << "of " << field.values.size() << " samples";
    }
}

// A glTF with one triangle instanced by two nodes: one translated, one under a scaled parent.
std::string gltfWithTransforms() {
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::string buffer(reinterpret_cast<const char*>(positions), sizeof positions);
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0, "translation": [10, 0, 0]}, {"scale": [2, 2, 2], "children": [2]}, {"mesh": 0, "translation": [0, 0, 5]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,)" + base64(buffer) + R"("}]})";
}

TEST_F(MeshFormats, NodeTransformsAndInstancesAreApplied) {
    const Mesh mesh = loadMesh(write("nodes.gltf", gltfWithTransforms()));
    ASSERT_EQ(mesh.triangleCount(), 2u);
    std::vector<glm::dvec3> corners;
    for (std::size_t t = 0; t < 2; ++t) {
        for (int c = 0; c < 3; ++c) corners.push_back(mesh.toWorld(glm::dvec3(mesh.vertex(t, c))));
    }
    auto has = [&](glm::dvec3 p) { return std::find(corners.begin(), corners.end(), p) != corners.end(); };
    EXPECT_TRUE(has({10, 0, 0}) && has({11, 0, 0}) && has({10, 1, 0})) << "first node: translated by (10, 0, 0)";
    EXPECT_TRUE(has({0, 0, 10}) && has({2, 0, 10}) && has({0, 2, 10})) << "second: translated by (0, 0, 5), then scaled by 2";
    EXPECT_EQ(mesh.worldBounds().min, glm::dvec3(0, 0, 0));
    EXPECT_EQ(mesh.worldBounds().max, glm::dvec3(11, 2, 10));
}

TEST_F(MeshFormats, PolygonsAreTriangulated) {
    // A quad and a triangle: the quad becomes two triangles.
    const Mesh mesh = loadMesh(write("quad.off", "OFF\n7 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n5 5 5\n6 5 5\n5 6 5\n4 0 1 2 3\n3 4 5 6\n"));
    EXPECT_EQ(mesh.triangleCount(), 3u);
}

TEST_F(MeshFormats, BadFilesAreOneLineErrors) {
    for (const auto& [name, contents] : std::vector<std::pair<std::string, std::string>>{
             {"garbage.stl", std::string("solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0\n")},
             {"garbage.ply", std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n")},
             {"garbage.glb", std::string("glTF\x02\x00\x00\x00 this is not a binary glTF", 34)},
             {"garbage.fbx", std::string("Kaydara FBX Binary  \x00\x1a\x00 truncated", 33)},
             {"empty.off", std::string("")}}) {
        SCOPED_TRACE(name);
        const std::string file = write(name, contents);
        const std::string message = errorFrom([&] { loadMesh(file); });
        EXPECT_EQ(message.rfind(file + ":", 0), 0u) << message; // "PATH: problem" or "PATH:LINE: problem"
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST_F(MeshFormats, FileWithoutTrianglesIsAnError) {
    const std::string points = write("points.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n");
    const std::string message = errorFrom([&] { loadMesh(points); });
    EXPECT_EQ(message.rfind(points + ": ", 0), 0u) << message;
    const std::string lines = write("lines.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n");
    EXPECT_CONTAINS(errorFrom([&] { loadMesh(lines); }), lines + ": ");
}

TEST_F(MeshFormats, UnknownExtensionIsAnError) {
    const std::string file = write("mesh.xyz", "v 0 0 0\n");
    const std::string message = errorFrom([&] { loadMesh(file); });
    EXPECT_CONTAINS(message, file);
    EXPECT_CONTAINS(message, "unknown mesh format");
    EXPECT_CONTAINS(message, ".stl");
    EXPECT_CONTAINS(errorFrom([&] { loadMesh(path("missing.stl")); }), "cannot open");
}

class MeshFormatsWithoutAssimp : public test::ScratchFolderTest {};

TEST_F(MeshFormatsWithoutAssimp, OtherFormatsAreAnErrorNamingTheFile) {
    if (SDFGEN_HAS_ASSIMP) GTEST_SKIP() << "built with Assimp";
    const std::string file = write("mesh.gltf", "{\"asset\": {\"version\": \"2.0\"}}\n");
    const std::string message = errorFrom([&] { loadMesh(file); });
    EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
    EXPECT_CONTAINS(message, "built without Assimp");
}

} // namespace
} // namespace sdfgen
