// sdfgen's own mesh readers (PLY, OFF, STL) and the checks before Assimp reads a glTF: what a file
// declares is read in full, or refused with a one-line error naming the file; counts are checked
// against the file's size before anything is allocated; what is skipped is warned about.
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"

#include "support/checks.hpp"
#if SDFGEN_HAS_ASSIMP
#include "assimp/gltf_guard.hpp"
#endif

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <chrono>
#include <csignal>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <random>
#include <string>
#include <sys/stat.h>
#include <thread>
#include <utility>
#include <sys/resource.h>
#include <unistd.h>
#include <vector>

namespace sdfgen {
namespace {

using test::errorFrom;

// An octagonal prism (closed): its sides as one triangle strip around it, each cap as a strip
// zig-zagging across it; the strips' triangles, by the rule that every second one is turned.
struct Prism {
    std::vector<glm::vec3> positions;
    std::vector<std::vector<int>> strips;
    std::vector<glm::uvec3> triangles() const {
        std::vector<glm::uvec3> out;
        for (const std::vector<int>& s : strips) {
            for (std::size_t k = 0; k + 2 < s.size(); ++k) {
                if (k % 2 == 0) out.emplace_back(s[k], s[k + 1], s[k + 2]);
                else out.emplace_back(s[k + 1], s[k], s[k + 2]);
            }
        }
        return out;
    }
};

Prism prism() {
    Prism p;
    const int n = 8;
    for (int i = 0; i < n; ++i) {
        const float a = float(i) * 6.2831853f / float(n);
        p.positions.emplace_back(std::cos(a), std::sin(a), -0.75f); // bottom: 0..7
    }
    for (int i = 0; i < n; ++i) p.positions.push_back(p.positions[std::size_t(i)] + glm::vec3(0, 0, 1.5f)); // top: 8..15
    std::vector<int> side;
    for (int i = 0; i <= n; ++i) {
        side.push_back(n + i % n);
        side.push_back(i % n);
    }
    std::vector<int> top{n}, bottom{0};
    for (int lo = 1, hi = n - 1; lo <= hi; ++lo, --hi) {
        top.push_back(n + lo);
        bottom.push_back(hi);
        if (lo != hi) {
            top.push_back(n + hi);
            bottom.push_back(lo);
        }
    }
    p.strips = {side, top, bottom};
    return p;
}

void appendBytes(std::string& out, const void* value, std::size_t size, bool bigEndian) {
    const auto* bytes = static_cast<const char*>(value);
    for (std::size_t i = 0; i < size; ++i) out += bytes[bigEndian ? size - 1 - i : i];
}

template <class T>
void append(std::string& out, T value, bool bigEndian) {
    appendBytes(out, &value, sizeof value, bigEndian);
}

enum class Encoding { Ascii, Little, Big };

// The prism as PLY: its strips in one tristrips list (-1 between them), or its triangles as faces.
std::string prismPly(const Prism& p, Encoding encoding, bool asStrips) {
    std::vector<int> strip;
    for (const std::vector<int>& s : p.strips) {
        if (!strip.empty()) strip.push_back(-1);
        strip.insert(strip.end(), s.begin(), s.end());
    }
    const std::vector<glm::uvec3> triangles = p.triangles();
    std::string text = "ply\nformat ";
    text += encoding == Encoding::Ascii ? "ascii" : encoding == Encoding::Little ? "binary_little_endian" : "binary_big_endian";
    text += " 1.0\nelement vertex " + std::to_string(p.positions.size()) + "\nproperty float x\nproperty float y\nproperty float z\n";
    text += asStrips ? "element tristrips 1\nproperty list int int vertex_indices\n"
                     : "element face " + std::to_string(triangles.size()) + "\nproperty list uchar int vertex_indices\n";
    text += "end_header\n";
    const bool big = encoding == Encoding::Big;
    for (const glm::vec3& v : p.positions) {
        for (int axis = 0; axis < 3; ++axis) {
            if (encoding == Encoding::Ascii) text += std::to_string(v[axis]) + (axis < 2 ? " " : "\n");
            else append(text, v[axis], big);
        }
    }
    if (encoding == Encoding::Ascii) {
        if (asStrips) {
            text += std::to_string(strip.size());
            for (int i : strip) text += " " + std::to_string(i);
            text += "\n";
        } else {
            for (const glm::uvec3& t : triangles) text += "3 " + std::to_string(t.x) + " " + std::to_string(t.y) + " " + std::to_string(t.z) + "\n";
        }
    } else if (asStrips) {
        append(text, std::int32_t(strip.size()), big);
        for (int i : strip) append(text, std::int32_t(i), big);
    } else {
        for (const glm::uvec3& t : triangles) {
            append(text, std::uint8_t(3), big);
            for (int c = 0; c < 3; ++c) append(text, std::int32_t(t[c]), big);
        }
    }
    return text;
}

std::uint32_t littleEndianAt(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
}

std::size_t peakResidentKiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return std::size_t(usage.ru_maxrss);
}

class MeshReaders : public test::ScratchFolderTest {
protected:
    // The Error loading `name` with `contents` gives: one line, naming the file first.
    std::string loadError(const std::string& name, const std::string& contents) {
        const std::string file = write(name, contents);
        const std::string message = errorFrom([&] { loadMesh(file); });
        EXPECT_EQ(message.rfind(file + ":", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        return message;
    }
};

TEST_F(MeshReaders, PlyTriangleStripsGiveTheTrianglesOfTheEquivalentFaceList) {
    const Prism p = prism();
    const std::vector<glm::uvec3> expected = p.triangles();
    ASSERT_EQ(expected.size(), 16u + 6u + 6u);
    BakeSettings settings;
    settings.res = 12;
    for (const Encoding encoding : {Encoding::Ascii, Encoding::Little, Encoding::Big}) {
        SCOPED_TRACE(int(encoding));
        const Mesh strips = loadMesh(write("strips.ply", prismPly(p, encoding, true)));
        const Mesh faces = loadMesh(write("faces.ply", prismPly(p, encoding, false)));
        EXPECT_EQ(strips.triangles, expected);
        EXPECT_EQ(faces.triangles, expected);
        EXPECT_EQ(strips.positions, faces.positions);
        EXPECT_TRUE(strips.warnings.empty()) << strips.warnings.front();
        // The alternation is right: every face of the closed prism points out of it.
        for (std::size_t t = 0; t < strips.triangleCount(); ++t) {
            const glm::vec3 centre = (strips.vertex(t, 0) + strips.vertex(t, 1) + strips.vertex(t, 2)) / 3.0f;
            EXPECT_GT(glm::dot(strips.faceNormals[t], centre), 0.0f) << "triangle " << t;
        }
        EXPECT_EQ(test::bakeMesh(strips, settings).field.dense().values, test::bakeMesh(faces, settings).field.dense().values);
    }
}

TEST_F(MeshReaders, PlyReadsEveryScalarTypeAndSkipsWhatItDoesNotUse) {
    // Big-endian; x, y, z of three types among other properties, a list in the vertex, an element
    // of lists before the faces, a ushort count with uint indices, a quad (two triangles).
    std::string text =
        "ply\nformat binary_big_endian 1.0\ncomment every type\nobj_info test\n"
        "element vertex 4\nproperty uchar red\nproperty float64 x\nproperty int16 junk\nproperty float y\n"
        "property list uint8 float32 extra\nproperty int z\n"
        "element edge 2\nproperty list char ushort corners\nproperty uint32 flags\n"
        "element face 2\nproperty int8 tag\nproperty list ushort uint vertex_indices\nproperty double quality\nend_header\n";
    const double xs[4] = {0.0, 1.5, 1.5, 0.0};
    const float ys[4] = {0.0f, 0.0f, 2.0f, 2.0f};
    for (int v = 0; v < 4; ++v) {
        append(text, std::uint8_t(200), true);
        append(text, xs[v], true);
        append(text, std::int16_t(-7), true);
        append(text, ys[v], true);
        append(text, std::uint8_t(2), true);
        append(text, 1.0f, true);
        append(text, 2.0f, true);
        append(text, std::int32_t(v == 3 ? -4 : 4), true);
    }
    for (int e = 0; e < 2; ++e) {
        append(text, std::int8_t(3), true);
        for (int i = 0; i < 3; ++i) append(text, std::uint16_t(i), true);
        append(text, std::uint32_t(0xdeadbeef), true);
    }
    append(text, std::int8_t(1), true);
    append(text, std::uint16_t(4), true);
    for (std::uint32_t i : {0u, 1u, 2u, 3u}) append(text, i, true);
    append(text, 0.5, true);
    append(text, std::int8_t(2), true);
    append(text, std::uint16_t(3), true);
    for (std::uint32_t i : {0u, 2u, 1u}) append(text, i, true);
    append(text, 0.25, true);
    const Mesh mesh = loadMesh(write("types.ply", text));
    ASSERT_EQ(mesh.positions.size(), 4u);
    const std::vector<glm::dvec3> world = mesh.worldPositions();
    EXPECT_EQ(world[1], glm::dvec3(1.5, 0, 4));
    EXPECT_EQ(world[3], glm::dvec3(0, 2, -4));
    EXPECT_EQ(mesh.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}, {0, 2, 1}}));

    // The same in ASCII with the other type names and the vertex_index spelling.
    const Mesh ascii = loadMesh(write("types-ascii.ply",
                                      "ply\nformat ascii 1.0\nelement vertex 4\nproperty uint8 red\nproperty double x\n"
                                      "property short junk\nproperty float32 y\nproperty list uchar float extra\nproperty int32 z\n"
                                      "element face 2\nproperty char tag\nproperty list uint16 uint32 vertex_index\nend_header\n"
                                      "200 0 -7 0 2 1 2 4\n200 1.5 -7 0 0 4\n200 1.5 -7 2 1 9 4\n200 0 -7 2 0 -4\n"
                                      "1 4 0 1 2 3\n-2 3 0 2 1\n"));
    EXPECT_EQ(ascii.worldPositions(), world);
    EXPECT_EQ(ascii.triangles, mesh.triangles);
}

TEST_F(MeshReaders, PlyFacesOfFewerThanThreeVerticesAreSkippedWithAWarning) {
    const std::string file = write("short-faces.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                                      "property float z\nelement face 3\nproperty list uchar int vertex_indices\n"
                                                      "end_header\n0 0 0\n1 0 0\n0 1 0\n0\n3 0 1 2\n2 0 1\n");
    const Mesh mesh = loadMesh(file);
    EXPECT_EQ(mesh.triangleCount(), 1u);
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_EQ(mesh.warnings[0], file + ": skipped 2 faces of fewer than 3 vertices");
}

TEST_F(MeshReaders, PlyCountsBeyondTheFileAreRefusedBeforeAllocating) {
    const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 200000000\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    std::string file = header + std::string(400 - header.size(), '\0');
    const auto start = std::chrono::steady_clock::now();
    EXPECT_CONTAINS(loadError("huge.ply", file), "declares 200000000 vertices (at least 2.4e+09 bytes) but only");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
    EXPECT_CONTAINS(loadError("huge-ascii.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                                "property float z\nelement face 2000000000\nproperty list uchar int vertex_indices\n"
                                                "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                    "declares 2000000000 faces");
    // A list claiming 4e9 items in a small file.
    std::string list = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                       "element face 1\nproperty list uint int vertex_indices\nend_header\n";
    for (int i = 0; i < 9; ++i) append(list, float(i % 2), false);
    append(list, std::uint32_t(4000000000u), false);
    for (int i = 0; i < 3; ++i) append(list, std::int32_t(i), false);
    EXPECT_CONTAINS(loadError("long-list.ply", list), "claims 4000000000 items");
}

TEST_F(MeshReaders, PlyIndicesOutOfRangeAreErrors) {
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
    EXPECT_CONTAINS(loadError("past.ply", header + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + vertices + "3 0 1 3\n"),
                    "face 1 of 1 refers to vertex 3 but the file has 3 vertices");
    EXPECT_CONTAINS(loadError("negative.ply", header + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + vertices + "3 0 -2 1\n"),
                    "refers to vertex -2");
    EXPECT_CONTAINS(loadError("strip.ply", header + "element tristrips 1\nproperty list int int vertex_indices\nend_header\n" + vertices + "5 0 1 2 -1 7\n"),
                    "tristrips 1 of 1 refers to vertex 7");
    EXPECT_CONTAINS(loadError("truncated.ply", header + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + vertices + "3 0 1\n"),
                    "the file ends inside face 1 of 1");
    EXPECT_CONTAINS(loadError("type.ply", header + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + vertices + "300 0 1 2\n"),
                    "'300' in face 1 of 1 is not a whole number of its type's range");
}

TEST_F(MeshReaders, PlyWithByteFlipsLoadsOrFailsCleanly) {
    const std::string valid = prismPly(prism(), Encoding::Little, false);
    const std::string stripsValid = prismPly(prism(), Encoding::Big, true);
    std::mt19937 random(12345);
    const auto start = std::chrono::steady_clock::now();
    int loaded = 0, refused = 0;
    for (int i = 0; i < 200; ++i) {
        std::string mutant = i % 2 ? valid : stripsValid;
        const int flips = 1 + int(random() % 4);
        for (int f = 0; f < flips; ++f) mutant[random() % mutant.size()] = char(random() % 256);
        if (i % 10 == 0) mutant.resize(random() % mutant.size());
        const std::string file = write("mutant.ply", mutant);
        try {
            const Mesh mesh = loadMesh(file);
            for (const glm::uvec3& t : mesh.triangles) ASSERT_LT(std::max({t.x, t.y, t.z}), mesh.positions.size());
            ++loaded;
        } catch (const Error& e) {
            ASSERT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
            ++refused;
        }
    }
    EXPECT_GT(loaded, 0);
    EXPECT_GT(refused, 0);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
}

TEST_F(MeshReaders, OffIsReadInFullOrRefused) {
    const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    const Mesh quad = loadMesh(write("quad.off", "# comment\nOFF 5 2 0\n0 0 0 1 0 0 1\n1 0 0\n1 1 0\n0 1 0\n0 0 5\n4 0 1 2 3 255 0 0\n2 0 4\n"));
    EXPECT_EQ(quad.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}));
    ASSERT_EQ(quad.warnings.size(), 2u);
    EXPECT_CONTAINS(quad.warnings[0], "quad.off: skipped 1 face of fewer than 3 vertices");
    EXPECT_CONTAINS(quad.warnings[1], "quad.off: 1 of 5 vertices are used by no triangle");

    EXPECT_CONTAINS(loadError("past.off", "OFF\n4 1 0\n" + vertices + "3 0 1 4\n"), ":7: face refers to vertex 4 but the file has 4 vertices");
    const auto start = std::chrono::steady_clock::now();
    EXPECT_CONTAINS(loadError("faces.off", "OFF\n4 2000000000 0\n" + vertices + "3 0 1 2\n"), "declares 2000000000 faces");
    EXPECT_CONTAINS(loadError("vertices.off", "OFF\n100000000 1 0\n" + vertices + "3 0 1 2\n"), "declares 100000000 vertices");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
    EXPECT_CONTAINS(loadError("short.off", "OFF\n4 2 0\n" + vertices + "3 0 1 2\n"), "the file ends after 1 of its 2 faces");
    EXPECT_CONTAINS(loadError("binary.off", "OFF BINARY\n"), "binary OFF files are not supported");

    const Mesh extra = loadMesh(write("extra.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n"));
    EXPECT_EQ(extra.triangleCount(), 1u);
    ASSERT_EQ(extra.warnings.size(), 1u);
    EXPECT_CONTAINS(extra.warnings[0], "1 lines after the 1 faces the header declares were not read");
}

TEST_F(MeshReaders, UnusedVerticesInBulkAreWarnedAbout) {
    std::string text = "OFF\n10 1 0\n0 0 0\n1 0 0\n0 1 0\n";
    for (int i = 0; i < 7; ++i) text += "5 5 " + std::to_string(i) + "\n";
    const std::string file = write("unused.off", text + "3 0 1 2\n");
    const Mesh mesh = loadMesh(file);
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_EQ(mesh.warnings[0], file + ": 7 of 10 vertices are used by no triangle");
}

TEST_F(MeshReaders, StlFacetsAreTrianglesAndCornersAreJoined) {
    const std::string facet = " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n";
    const std::string second = " FACET NORMAL 0 0 -1\n  OUTER LOOP\n   VERTEX 0 0 0\n   VERTEX 0 1 0\n   VERTEX -1 0 -0\n  ENDLOOP\n ENDFACET\n";
    const Mesh mesh = loadMesh(write("two.stl", "solid a\n" + facet + "endsolid a\nsolid b\n" + second + "endsolid\n"));
    EXPECT_EQ(mesh.positions.size(), 4u); // the shared corners are one vertex each
    EXPECT_EQ(mesh.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}));

    const std::string four = " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n   vertex 1 1 0\n  endloop\n endfacet\n";
    EXPECT_CONTAINS(loadError("four.stl", "solid x\n" + four + "endsolid x\n"), ":7: a facet has more than 3 vertices (an STL facet has 3)");
    EXPECT_CONTAINS(loadError("unfinished.stl", "solid x\n" + facet), "the file ends without 'endsolid'");

    std::string binary(80, '\0');
    append(binary, std::uint32_t(1000000), false);
    binary += std::string(50, '\0');
    EXPECT_CONTAINS(loadError("short.stl", binary), "a binary STL file declaring 1000000 triangles has 50000084 bytes, this one 134");
}

// A glTF of one triangle, its indices (uint32) given; extra JSON members added at the top level.
std::string gltfTriangle(std::uint32_t lastIndex, const std::string& extra = "", const std::string& nodes = R"([{"mesh": 0}])") {
    std::string buffer;
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) append(buffer, v, false);
    for (std::uint32_t i : {0u, 1u, lastIndex}) append(buffer, i, false);
    std::string b64;
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (std::size_t i = 0; i < buffer.size(); i += 3) { // 48 bytes: no padding
        const std::uint32_t n = std::uint32_t(std::uint8_t(buffer[i])) << 16 | std::uint32_t(std::uint8_t(buffer[i + 1])) << 8 | std::uint8_t(buffer[i + 2]);
        for (int s = 18; s >= 0; s -= 6) b64 += digits[(n >> s) & 63];
    }
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": )" + nodes + R"(,
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
  "buffers": [{"byteLength": 48, "uri": "data:application/octet-stream;base64,)" + b64 + "\"}]" + extra + "}";
}

TEST_F(MeshReaders, GltfIsCheckedBeforeAssimpReadsIt) {
    const Mesh good = loadMesh(write("good.gltf", gltfTriangle(2)));
    EXPECT_EQ(good.triangleCount(), 1u);
    EXPECT_TRUE(good.warnings.empty()) << good.warnings.front(); // Assimp read what the file declares
    // Two nodes instancing it, one under the other: two triangles, as declared.
    const Mesh twice = loadMesh(write("twice.gltf", gltfTriangle(2, "", R"([{"mesh": 0, "children": [1]}, {"mesh": 0, "translation": [0, 0, 1]}])")));
    EXPECT_EQ(twice.triangleCount(), 2u);
    EXPECT_TRUE(twice.warnings.empty()) << twice.warnings.front();
    EXPECT_CONTAINS(loadError("index.gltf", gltfTriangle(4000000000u)), "mesh 0 primitive 0 refers to vertex 4000000000 but it has 3 vertices");

    // 30,000 nested nodes; a cycle; JSON nested 100,000 deep.
    std::string nested = "[";
    for (int n = 0; n < 30000; ++n) nested += std::string(n ? "," : "") + (n < 29999 ? R"({"children": [)" + std::to_string(n + 1) + "]}" : R"({"mesh": 0})");
    EXPECT_CONTAINS(loadError("deep.gltf", gltfTriangle(2, "", nested + "]")), "its node tree is deeper than 1000 levels");
    EXPECT_CONTAINS(loadError("cycle.gltf", gltfTriangle(2, "", R"([{"mesh": 0, "children": [1]}, {"children": [0]}])")), "a cycle in the node tree");
    EXPECT_CONTAINS(loadError("json.gltf", gltfTriangle(2, R"(, "extras": )" + std::string(100000, '[') + std::string(100000, ']'))),
                    "its JSON nests deeper than 200 levels");
    // Each node instancing the next twice, 64 deep: 2^64 copies of the triangle.
    std::string doubling = "[";
    for (int n = 0; n < 64; ++n) doubling += (n ? "," : "") + (n < 63 ? R"({"mesh": 0, "children": [)" + std::to_string(n + 1) + "," + std::to_string(n + 1) + "]}" : R"({"mesh": 0})");
    EXPECT_CONTAINS(loadError("instances.gltf", gltfTriangle(2, "", doubling + "]")), "more than the 2^32 - 1 vertices sdfgen supports");
    // Views and accessors outside what they refer to (Assimp checks an accessor's count times
    // its component size, not its element size, against the view).
    std::string view = gltfTriangle(2);
    view.replace(view.find(R"("byteOffset": 36, "byteLength": 12)"), 34, R"("byteOffset": 40, "byteLength": 12)");
    EXPECT_CONTAINS(loadError("view.gltf", view), "bufferView 1 (bytes 40 + 12) is outside buffer 0 (48 bytes)");
    std::string accessor = gltfTriangle(2);
    accessor.replace(accessor.find(R"("count": 3, "type": "VEC3")"), 26, R"("count": 9, "type": "VEC3")");
    EXPECT_CONTAINS(loadError("accessor.gltf", accessor), "accessor 0 (9 elements of 12 bytes from byte 0) does not fit bufferView 0 (36 bytes)");
    // A sparse accessor: patching vertex 0 with itself reads; indices past their view do not.
    std::string sparse = gltfTriangle(2);
    sparse.replace(sparse.find(R"("max": [1, 1, 0]})"), 17,
                   R"("max": [1, 1, 0], "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5121}, "values": {"bufferView": 0}}})");
    EXPECT_EQ(loadMesh(write("sparse.gltf", sparse)).triangleCount(), 1u);
    sparse.replace(sparse.find(R"("componentType": 5121})"), 22, R"("componentType": 5121, "byteOffset": 100000})");
    EXPECT_CONTAINS(loadError("sparse-indices.gltf", sparse), "accessor 0's sparse indices (1 of 1 bytes from byte 100000) do not fit their bufferView (12 bytes)");
    std::string quantized = gltfTriangle(2);
    quantized.replace(quantized.find(R"("componentType": 5126)"), 21, R"("componentType": 5121)");
    EXPECT_CONTAINS(loadError("quantized.gltf", quantized), "mesh 0 primitive 0's positions are integers (KHR_mesh_quantization)");
    EXPECT_CONTAINS(loadError("version.gltf", R"({"asset": {"version": "1.0"}})"), "only glTF 2.x files are read");
}

// A GLB of `json` (padded with spaces to 4 bytes unless `padded` is false, as Assimp reads
// either) and a binary chunk holding `bin`.
std::string glb(std::string json, const std::string& bin, bool padded = true) {
    while (padded && json.size() % 4) json += ' ';
    const std::size_t padding = (4 - json.size() % 4) % 4;
    std::string out = "glTF";
    append(out, std::uint32_t(2), false);
    append(out, std::uint32_t(12 + 8 + json.size() + padding + 8 + bin.size()), false);
    append(out, std::uint32_t(json.size()), false);
    out += "JSON" + json + std::string(padding, ' ');
    append(out, std::uint32_t(bin.size()), false);
    return out + std::string("BIN\0", 4) + bin;
}

// The triangle's 48 bytes: positions, then indices (the last one given).
std::string triangleBytes(std::uint32_t lastIndex = 2) {
    std::string bin;
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) append(bin, v, false);
    for (std::uint32_t i : {0u, 1u, lastIndex}) append(bin, i, false);
    return bin;
}

// The triangle as GLB, its buffer in the binary chunk.
std::string glbTriangle(bool padded = true) {
    std::string json = gltfTriangle(2);
    json.replace(json.find(R"(, "uri")"), json.find("}]", json.find(R"(, "uri")")) - json.find(R"(, "uri")"), "");
    return glb(json, triangleBytes(), padded);
}

TEST_F(MeshReaders, PlyWithTwoVertexElementsIsRefused) {
    // The second element's vertices would silently replace the first's.
    const std::string element = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    EXPECT_CONTAINS(loadError("two.ply", "ply\nformat ascii 1.0\n" + element + element +
                                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                             "0 0 0\n1 0 0\n0 1 0\n5 5 5\n6 5 5\n5 6 5\n3 0 1 2\n"),
                    "two.ply: the header declares more than one vertex element");
}

TEST_F(MeshReaders, CoordinatesBeyondSinglePrecisionAreNamed) {
    // Not "all triangles have zero area" (the other vertices lost in the huge one's rounding).
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty double z\n"
                               "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    EXPECT_CONTAINS(loadError("huge.ply", header + "0 0 0\n1 0 1e300\n0 1 0\n3 0 1 2\n"),
                    "huge.ply:11: vertex coordinate '1e+300' is beyond single precision's range (3.4e+38) in vertex 2 of 3");
    std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
                         "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1e39, 0.0}) append(binary, v, false);
    append(binary, std::uint8_t(3), false);
    for (std::int32_t i : {0, 1, 2}) append(binary, i, false);
    EXPECT_CONTAINS(loadError("huge-binary.ply", binary), "vertex coordinate '-1e+39' is beyond single precision's range (3.4e+38) in vertex 3 of 3");
    EXPECT_CONTAINS(loadError("huge.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1e300 0\n3 0 1 2\n"),
                    "huge.off:5: vertex coordinate '1e300' is beyond single precision's range");
    EXPECT_CONTAINS(loadError("huge.stl", "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1e300 0 0\n"
                                          "   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n"),
                    "huge.stl:5: vertex coordinate '1e+300' is beyond single precision's range");
}

TEST_F(MeshReaders, ByteOrderMarkIsSkippedInEveryTextFormat) {
    const std::string bom = "\xEF\xBB\xBF";
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const std::string stl = "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n"
                            " endfacet\nendsolid t\n";
    for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
             {"bom.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
             {"bom.ply", ply},
             {"bom.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
             {"bom.stl", stl},
             {"bom.gltf", gltfTriangle(2)}}) {
        const Mesh mesh = loadMesh(write(name, bom + text));
        EXPECT_EQ(mesh.triangleCount(), 1u) << name;
        EXPECT_EQ(mesh.positions.size(), 3u) << name;
    }
    // Line numbers still count from the first line.
    EXPECT_CONTAINS(loadError("bad.off", bom + "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), "bad.off:6:");
}

TEST_F(MeshReaders, GlbChunkLengthsAreChecked) {
    const std::string glb = glbTriangle();
    EXPECT_EQ(loadMesh(write("good.glb", glb)).triangleCount(), 1u);
    std::string json = glb;
    const std::uint32_t huge = 0x7fffffff;
    std::memcpy(json.data() + 12, &huge, 4);
    EXPECT_CONTAINS(loadError("json.glb", json), "the JSON chunk declares 2147483647 bytes but only");
    std::string total = glb;
    std::memcpy(total.data() + 8, &huge, 4);
    EXPECT_CONTAINS(loadError("total.glb", total), "the header declares 2147483647 bytes but the file has");
    std::string bin = glb;
    const std::size_t binHeader = 20 + littleEndianAt(glb, 12);
    std::memcpy(bin.data() + binHeader, &huge, 4);
    EXPECT_CONTAINS(loadError("bin.glb", bin), "the binary chunk declares 2147483647 bytes but only 48 follow it");
}

TEST_F(MeshReaders, GltfExternalBufferIsReadOnlyAsFarAsItsViewsGo) {
    // A 3 GB buffer file (sparse: no disk used) of which the views use 48 bytes.
    std::string gltf = gltfTriangle(2);
    const std::size_t uri = gltf.find(R"("byteLength": 48, "uri")");
    gltf.replace(uri, gltf.find("}]", uri) - uri, R"("byteLength": 3000000000, "uri": "big.bin")");
    const std::string binFile = write("big.bin", triangleBytes());
    ASSERT_EQ(truncate(binFile.c_str(), 3000000000), 0);
    const std::size_t before = peakResidentKiB();
    EXPECT_EQ(loadMesh(write("big.gltf", gltf)).triangleCount(), 1u);
    EXPECT_LT(peakResidentKiB() - before, std::size_t(256) << 10) << "KiB more at the peak";
    // More than the file holds.
    ASSERT_EQ(truncate(binFile.c_str(), 1000), 0);
    EXPECT_CONTAINS(loadError("short.gltf", gltf), "buffer 0 declares 3000000000 bytes but its file 'big.bin' has 1000");
}

TEST_F(MeshReaders, PointsAndLinesFromAssimpAreWarnedAbout) {
    std::string gltf = gltfTriangle(2);
    gltf.replace(gltf.find(R"("indices": 1})"), 13, R"("indices": 1}, {"attributes": {"POSITION": 0}, "mode": 0})");
    const Mesh mesh = loadMesh(write("points.gltf", gltf));
    EXPECT_EQ(mesh.triangleCount(), 1u);
    ASSERT_FALSE(mesh.warnings.empty());
    EXPECT_CONTAINS(mesh.warnings[0], "skipped 3 points and lines");
}

// The triangle with its buffer in the external file `uri`; extra JSON members at the top level.
std::string gltfWithBufferFile(const std::string& uri, const std::string& extra = "") {
    std::string gltf = gltfTriangle(2, extra);
    const std::size_t at = gltf.find(R"("uri")");
    return gltf.replace(at, gltf.find("}]", at) - at, R"("uri": ")" + uri + "\"");
}

TEST_F(MeshReaders, GltfExternalFilesAreConfinedToItsFolder) {
    std::filesystem::create_directories(dir_ / "model" / "sub");
    // A valid buffer outside the glTF's folder, starting with bytes no error may show.
    write("outside.bin", triangleBytes());
    write("model/sub/inside.bin", triangleBytes());
    EXPECT_EQ(loadMesh(write("model/inside.gltf", gltfWithBufferFile("sub/inside.bin"))).triangleCount(), 1u);
    EXPECT_EQ(loadMesh(write("model/sub/up.gltf", gltfWithBufferFile("../sub/inside.bin"))).triangleCount(), 1u);

    const std::string outside = loadError("model/up.gltf", gltfWithBufferFile("../outside.bin"));
    EXPECT_CONTAINS(outside, "buffer 0's uri '../outside.bin' leads outside the glTF's folder (SDFGEN_GLTF_FOLDERS lists more");
    const std::string absolute = (dir_ / "outside.bin").string();
    EXPECT_CONTAINS(loadError("model/absolute.gltf", gltfWithBufferFile(absolute)), "buffer 0's uri '/tmp/");
    EXPECT_CONTAINS(loadError("model/absolute.gltf", gltfWithBufferFile(absolute)), "' is an absolute path");
    std::filesystem::create_symlink(dir_ / "outside.bin", dir_ / "model" / "link.bin");
    EXPECT_CONTAINS(loadError("model/link.gltf", gltfWithBufferFile("link.bin")), "buffer 0's uri 'link.bin' leads outside the glTF's folder");
    std::filesystem::create_directory_symlink(dir_, dir_ / "model" / "linked");
    EXPECT_CONTAINS(loadError("model/folder.gltf", gltfWithBufferFile("linked/outside.bin")), "leads outside the glTF's folder");
    // Images are not read, but named only inside too.
    EXPECT_CONTAINS(loadError("model/image.gltf", gltfWithBufferFile("sub/inside.bin", R"(, "images": [{"uri": "../../etc/passwd"}])")),
                    "image 0's uri '../../etc/passwd' leads outside the glTF's folder");

    // Folders allowed by the user, each with its subfolders.
    setenv("SDFGEN_GLTF_FOLDERS", (":" + dir_.string() + ":").c_str(), 1);
    EXPECT_EQ(loadMesh(dir_ / "model" / "up.gltf").triangleCount(), 1u);
    EXPECT_EQ(loadMesh(dir_ / "model" / "link.gltf").triangleCount(), 1u);
    EXPECT_CONTAINS(loadError("model/absolute.gltf", gltfWithBufferFile(absolute)), "is an absolute path");
    setenv("SDFGEN_GLTF_FOLDERS", (dir_ / "missing").c_str(), 1);
    EXPECT_CONTAINS(loadError("model/up.gltf", gltfWithBufferFile("../outside.bin")), "', which is not a folder");
    unsetenv("SDFGEN_GLTF_FOLDERS");
}

TEST_F(MeshReaders, GltfUnderAnotherNameIsCheckedAllTheSame) {
    // Assimp takes a file whose extension no importer (or several) claims for glTF by its content:
    // a glTF named .xml had its buffers read from wherever its URIs led. Every name Assimp is
    // handed gets the guard by content; .obj, .ply, .off, .stl and no extension are sdfgen's own readers.
    std::filesystem::create_directories(dir_ / "model");
    write("outside.bin", triangleBytes());
    write("model/inside.bin", triangleBytes());
    for (const char* name : {"t.xml", "t.mesh.xml", "t.fbx", "t.dae", "t.x"}) {
        SCOPED_TRACE(name);
        const std::string base = std::string("model/") + name;
        EXPECT_CONTAINS(loadError(base, gltfWithBufferFile("../outside.bin")), "buffer 0's uri '../outside.bin' leads outside the glTF's folder");
        EXPECT_CONTAINS(loadError("model/bom-" + std::string(name), "\xEF\xBB\xBF \n" + gltfWithBufferFile("../outside.bin")),
                        "leads outside the glTF's folder");
        EXPECT_CONTAINS(loadError("model/bin-" + std::string(name), glb(gltfTriangle(2), triangleBytes(4000000000u))),
                        "buffer 0 has a uri, but in a GLB file buffer 0 is read from the binary chunk");
    }
    // Nor does a .xml reach Assimp's importers of other names by content (an OFF claiming 4.6e11
    // vertices made Assimp allocate 46 GB; OpenGEX tokens made its parser read past its buffer).
    for (const char* content : {"OFF\n3 455555555555 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "ply\nformat ascii 1.0\nelement vertex 4000000000\n",
                                "indexarray{\"version\""}) {
        SCOPED_TRACE(content);
        EXPECT_CONTAINS(loadError("model/own.xml", content), "cannot read the file");
    }
    // Where Assimp does read it as glTF (JSON named .xml; it takes GLB by its name only), the guarded glTF is read.
    EXPECT_EQ(loadMesh(write("model/good.xml", gltfWithBufferFile("inside.bin"))).triangleCount(), 1u);
}

TEST_F(MeshReaders, FilesAModelRefersToAreNotRead) {
    // Assimp's importers open files a model names or files beside it: an MD5 mesh its animation.
    std::filesystem::create_directories(dir_ / "model");
    const std::string md5 = "MD5Version 10\ncommandline \"\"\nnumJoints 1\nnumMeshes 1\njoints {\n\"origin\" -1 ( 0 0 0 ) ( 0 0 0 )\n}\n"
                            "mesh {\nnumverts 3\nvert 0 ( 0 0 ) 0 1\nvert 1 ( 0 0 ) 1 1\nvert 2 ( 0 0 ) 2 1\nnumtris 1\ntri 0 0 2 1\n"
                            "numweights 3\nweight 0 0 1.0 ( 0 0 0 )\nweight 1 0 1.0 ( 1 0 0 )\nweight 2 0 1.0 ( 0 1 0 )\n}\n";
    try { // nothing beside it to read (the mesh itself is Assimp's to take or leave)
        loadMesh(write("model/alone.md5mesh", md5));
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).find("refers to"), std::string::npos) << e.what();
    }
    write("model/t.md5anim", "MD5Version 10\n");
    EXPECT_CONTAINS(loadError("model/t.md5mesh", md5), "refers to another file, '");
    EXPECT_CONTAINS(loadError("model/t.md5mesh", md5), "t.md5anim', which sdfgen does not read (a mesh read through Assimp must be one file");

    // Ogre meshes name their skeleton and materials anywhere, and one flipped byte of a valid one
    // (a submesh without vertices) crashed Assimp: refused by their name.
    const std::string ogre = R"(<mesh><sharedgeometry vertexcount="3"><vertexbuffer positions="true">)"
                             R"(<vertex><position x="0" y="0" z="0"/></vertex><vertex><position x="1" y="0" z="0"/></vertex>)"
                             R"(<vertex><position x="0" y="1" z="0"/></vertex></vertexbuffer></sharedgeometry><submeshes>)"
                             R"(<submesh material="m" usesharedv\x9certices="true" operationtype="triangle_list"><faces count="1">)"
                             R"(<face v1="0" v2="1" v3="2"/></faces></submesh></submeshes></mesh>)";
    EXPECT_CONTAINS(loadError("model/crash.mesh.xml", ogre), "Ogre meshes are not read");
    EXPECT_CONTAINS(loadError("model/crash.MESH.xml", ogre), "Ogre meshes are not read");
    EXPECT_CONTAINS(loadError("model/binary.mesh", ogre), "Ogre meshes are not read");

    // A LightWave scene's objects are all other files (Assimp loads them with every importer, tries
    // ../ and ../../ too, recursed into a scene naming itself until the stack overflowed, and aborts
    // on an empty name): refused by its name.
    const std::string lightwave = "a LightWave scene holds no geometry of its own";
    write("outside.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_CONTAINS(loadError("model/up.lws", "LWSC\n3\n\nLoadObjectLayer 1 ../outside.obj\n"), lightwave);
    EXPECT_CONTAINS(loadError("model/loop.LWS", "LWSC\n3\n\nLoadObjectLayer 1 loop.LWS\n"), lightwave);
    EXPECT_CONTAINS(loadError("model/empty.lws", std::string("LWSC\n3\n\nLoadObjectLayer 1") + '\0' + " ../outside.obj\n"), lightwave);
    EXPECT_CONTAINS(loadError("model/motion.mot", "LWMO\n3\n"), lightwave);

    // Assimp 5.2's Irrlicht scene importer never makes a mesh node (it compares the type attribute's
    // name, not its value), so it loads nothing it names; from 5.3 it does, through the same checks.
    const std::string irr = R"(<?xml version="1.0"?><irr_scene><node type="mesh"><attributes>)"
                            R"(<string name="Mesh" value="../outside.obj" /></attributes></node></irr_scene>)";
    const std::string irrProblem = loadError("model/scene.irr", irr);
    EXPECT_TRUE(irrProblem.find("refers to another file, '") != std::string::npos || irrProblem.find("the file holds no complete scene") != std::string::npos) << irrProblem;
    // Its X3D importer opens its own file twice at once: that is not a file naming itself.
    const std::string x3d = "<?xml version=\"1.0\"?><X3D version='3.3'><Scene><Shape><IndexedFaceSet coordIndex='0 1 2 -1'>"
                            "<Coordinate point='0 0 0 1 0 0 0 1 0'/></IndexedFaceSet></Shape></Scene></X3D>";
    EXPECT_EQ(loadMesh(write("model/t.x3d", x3d)).triangleCount(), 1u);
}

TEST_F(MeshReaders, GltfIsReadOnceAndAssimpParsesTheBytesChecked) {
    // A FIFO yields its bytes once. Told apart as glTF by name or content, checked and parsed by
    // Assimp from that one reading: a file changed or swapped after the check is not read again.
    struct sigaction ignore {}, before {};
    ignore.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ignore, &before); // a reader that gives up must fail the test, not end it
    for (const auto& file : {std::pair<std::string, std::string>{"pipe.gltf", gltfTriangle(2)}, {"pipe.xml", gltfTriangle(2)},
                             {"pipe.glb", glbTriangle()}}) {
        SCOPED_TRACE(file.first);
        const std::string fifo = (dir_ / file.first).string();
        ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
        std::thread writer([&] { std::ofstream(fifo, std::ios::binary) << file.second; });
        std::string problem;
        try {
            EXPECT_EQ(loadMesh(fifo).triangleCount(), 1u);
        } catch (const Error& e) {
            problem = e.what();
        }
        const int unblock = open(fifo.c_str(), O_RDONLY | O_NONBLOCK); // for a writer still waiting for a reader
        writer.join();
        close(unblock);
        EXPECT_EQ(problem, "");
    }
    sigaction(SIGPIPE, &before, nullptr);
}

#if SDFGEN_HAS_ASSIMP
// The guard itself (the Assimp plug-in's code, built into the tests too): what it hands Assimp in
// place of the files is what it checked, not what the files hold afterwards.
TEST_F(MeshReaders, GltfGuardHandsAssimpTheBytesItChecked) {
    const std::string checked = gltfWithBufferFile("b.bin");
    const std::string path = write("t.gltf", "not read: the guard is given the bytes");
    write("b.bin", triangleBytes());
    const GltfCheck check = guardGltf(path, checked, false);
    write("b.bin", triangleBytes(4000000000u)); // changed after the check
    EXPECT_EQ(check.bytes, checked);
    ASSERT_EQ(check.externalFiles.size(), 1u);
    EXPECT_EQ(check.externalFiles.begin()->first, (dir_ / "b.bin").string());
    EXPECT_EQ(check.externalFiles.begin()->second, triangleBytes());
    EXPECT_CONTAINS(errorFrom([&] { guardGltf(path, checked, false); }), "refers to vertex 4000000000 but it has 3 vertices");
}
#endif

TEST_F(MeshReaders, GltfIndicesAreCheckedAsAssimpReadsThem) {
    const auto replace = [](std::string& text, const std::string& from, const std::string& to) { text.replace(text.find(from), from.size(), to); };
    // A sparse accessor patching index 0 with the bytes of the float 1.0 (vertex 1065353216).
    std::string sparse = gltfTriangle(2);
    replace(sparse, R"("count": 3, "type": "SCALAR"})",
            R"("count": 3, "type": "SCALAR", "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5121}, "values": {"bufferView": 0, "byteOffset": 12}}})");
    EXPECT_CONTAINS(loadError("sparse-index.gltf", sparse), "mesh 0 primitive 0's indices accessor is sparse, which sdfgen does not read");
    // Assimp copies a sparse accessor's elements packed but reads them at the view's stride: 12 bytes
    // past its copy of 36 here.
    std::string strided = gltfTriangle(2);
    replace(strided, R"({"buffer": 0, "byteLength": 36})", R"({"buffer": 0, "byteLength": 48, "byteStride": 16})");
    replace(strided, R"("max": [1, 1, 0]})",
            R"("max": [1, 1, 0], "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5121}, "values": {"bufferView": 0}}})");
    EXPECT_CONTAINS(loadError("sparse-strided.gltf", strided), "accessor 0's sparse patches an accessor on an interleaved (strided) bufferView");

    // A GLB whose buffer 0 has a data URI of a good triangle, while Assimp reads the binary chunk:
    // index 4e9 there.
    EXPECT_CONTAINS(loadError("data-uri.glb", glb(gltfTriangle(2), triangleBytes(4000000000u))),
                    "buffer 0 has a uri, but in a GLB file buffer 0 is read from the binary chunk");
    // The binary chunk follows the JSON chunk padded to 4 bytes, whatever its length says.
    std::string json = gltfTriangle(2);
    json.replace(json.find(R"(, "uri")"), json.find("}]", json.find(R"(, "uri")")) - json.find(R"(, "uri")"), "");
    if (json.size() % 4 == 0) json += ' ';
    EXPECT_EQ(loadMesh(write("unpadded.glb", glb(json, triangleBytes(), false))).triangleCount(), 1u);
    EXPECT_CONTAINS(loadError("unpadded-index.glb", glb(json, triangleBytes(4000000000u), false)), "refers to vertex 4000000000 but it has 3 vertices");
}

} // namespace
} // namespace sdfgen
