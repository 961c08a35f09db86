// The setup phases (tree build, topology, mesh check, crossing scan) in parallel: the same results
// for any thread count.
#include "core/bvh.hpp"
#include "core/sign.hpp"
#include "core/topology.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <limits>
#include <memory>

namespace sdfgen {
namespace {

Mesh overlappingShells(int levels) {
    const Mesh sphere = test::icosphere(1.0f, levels);
    std::vector<glm::dvec3> positions = sphere.worldPositions();
    std::vector<glm::uvec3> triangles = sphere.triangles;
    for (const glm::dvec3& p : sphere.worldPositions()) positions.push_back(p + glm::dvec3(0.61, 0.23, -0.17));
    for (const glm::uvec3& t : sphere.triangles) triangles.push_back(t + glm::uvec3(unsigned(sphere.positions.size())));
    return buildMesh("overlapping shells", positions, triangles);
}

// The triangles a box around everything reaches, in the order the tree visits them: equal for
// two trees only if their leaves are laid out alike.
std::vector<std::uint32_t> visitOrder(const Bvh& tree) {
    const float big = std::numeric_limits<float>::max();
    std::vector<std::uint32_t> order;
    tree.forEachOverlap({glm::vec3(-big), glm::vec3(big)}, [&](std::uint32_t t) { order.push_back(t); });
    return order;
}

TEST(SetupPhases, MeshCheckCountsAreTheSameForAnyThreadCount) {
    const Mesh mesh = overlappingShells(4);
    const Bvh tree(mesh);
    const MeshTopology topology(mesh);
    RunControl one;
    one.threads = 1;
    const MeshCheck serial = topology.check(mesh, tree, one);
    EXPECT_GT(serial.selfIntersections, 100u);
    EXPECT_EQ(serial.boundaryEdges, 0u);
    for (int threads : {2, 3, 8}) {
        RunControl control;
        control.threads = threads;
        const MeshCheck check = topology.check(mesh, tree, control);
        EXPECT_EQ(check.selfIntersections, serial.selfIntersections) << threads << " threads";
        EXPECT_EQ(check.describe(), serial.describe()) << threads << " threads";
    }
}

// Subtrees above a few thousand triangles are built in parallel and spliced: the layout must be
// the serial one exactly (same nodes, same leaf order), so queries are too.
TEST(SetupPhases, ParallelTreeBuildGivesTheSerialLayout) {
    const Mesh mesh = overlappingShells(5); // 40960 triangles: several levels built in parallel
    std::unique_ptr<Bvh> serial;
    tbb::task_arena(1).execute([&] { serial = std::make_unique<Bvh>(mesh); });
    for (int threads : {2, 4}) {
        std::unique_ptr<Bvh> parallel;
        tbb::task_arena(threads).execute([&] { parallel = std::make_unique<Bvh>(mesh); });
        EXPECT_EQ(parallel->nodeCount(), serial->nodeCount());
        EXPECT_EQ(parallel->depth(), serial->depth());
        EXPECT_EQ(visitOrder(*parallel), visitOrder(*serial));
        const glm::vec3 corner = mesh.vertex(1000, 0); // local coordinates, as the tree's
        const float reach = 0.05f * mesh.bounds.extent().x;
        const Bounds box{corner - reach, corner + reach};
        std::vector<std::uint32_t> a, b;
        serial->forEachOverlap(box, [&](std::uint32_t t) { a.push_back(t); });
        parallel->forEachOverlap(box, [&](std::uint32_t t) { b.push_back(t); });
        EXPECT_EQ(a, b);
        EXPECT_FALSE(a.empty());
    }
    EXPECT_EQ(visitOrder(*serial).size(), mesh.triangleCount());
}

} // namespace
} // namespace sdfgen
