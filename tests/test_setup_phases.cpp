// The setup phases (tree build, topology, mesh check, crossing scan): the same results for any
// thread count, progress that never runs backwards, and cancel honoured inside each.
#include "core/accel/bvh.hpp"
#include "core/sign/winding_sign.hpp"
#include "core/accel/topology.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/model.hpp"
#include "support/binary_rays.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <atomic>
#include <functional>
#include <limits>
#include <mutex>

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

// Regression (a Debug build found it): two mirror-symmetric shells cross only where their edges
// meet, exactly; the check tested edges against triangle interiors alone and counted no crossing
// at -O0 (at -O3 fused multiply-adds' rounding happened to find some). Edge-through-edge counts.
TEST(SetupPhases, MeshCheckCountsEdgeThroughEdgeCrossings) {
    // In exact integers: A's edge on the z axis passes through the edge y = z = 0 shared by B and
    // B'; A and B' overlap along the segment from the origin to (0, -1, 0), A touches B there.
    const Mesh mesh = buildMesh("edge through edge",
                                std::vector<glm::dvec3>{{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {-1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
                                {{0, 1, 2}, {3, 4, 5}, {4, 3, 6}});
    EXPECT_EQ(MeshTopology(mesh).check(mesh, Bvh(mesh)).selfIntersections, 2u);
    // Two unit spheres, their centres 1 apart on x: mirror images of each other.
    const Mesh sphere = test::icosphere(1.0f, 2);
    std::vector<glm::dvec3> positions;
    for (const glm::dvec3& p : sphere.worldPositions()) positions.push_back(p - glm::dvec3(0.5, 0, 0));
    for (const glm::dvec3& p : sphere.worldPositions()) positions.push_back(p + glm::dvec3(0.5, 0, 0));
    std::vector<glm::uvec3> triangles = sphere.triangles;
    for (const glm::uvec3& t : sphere.triangles) triangles.push_back(t + glm::uvec3(unsigned(sphere.positions.size())));
    const Mesh shells = buildMesh("mirror shells", positions, triangles);
    EXPECT_GE(MeshTopology(shells).check(shells, Bvh(shells)).selfIntersections, 64u);
}

// Subtrees above a few thousand triangles are built in parallel and spliced: the layout must be
// the serial one exactly (same nodes, same leaf order), so queries are too.
TEST(SetupPhases, ParallelTreeBuildGivesTheSerialLayout) {
    const Mesh mesh = overlappingShells(5); // 40960 triangles: several levels built in parallel
    RunControl one;
    one.threads = 1;
    const auto serial = std::make_unique<Bvh>(mesh, one);
    for (int threads : {2, 4}) {
        RunControl control;
        control.threads = threads;
        const auto parallel = std::make_unique<Bvh>(mesh, control);
        EXPECT_EQ(parallel->nodeCount(), serial->nodeCount());
        EXPECT_EQ(test::treeDepth(*parallel), test::treeDepth(*serial));
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

// What a phase reported, and a cancel flag it may raise itself after `cancelAfter` reports.
struct Watch {
    std::mutex mutex;
    std::vector<double> reports;
    std::atomic<bool> cancel{false};
    int cancelAfter = -1;

    RunControl control(int threads = 0) {
        RunControl c;
        c.threads = threads;
        c.cancel = &cancel;
        c.progress = [this](double f) {
            std::lock_guard<std::mutex> lock(mutex);
            reports.push_back(f);
            if (int(reports.size()) == cancelAfter) cancel = true;
        };
        return c;
    }
    void expectMonotoneToOne(const char* phase) {
        ASSERT_GE(reports.size(), 2u) << phase;
        for (std::size_t i = 1; i < reports.size(); ++i) ASSERT_LE(reports[i - 1], reports[i]) << phase << " report " << i;
        EXPECT_EQ(reports.back(), 1.0) << phase;
    }
};

using Phase = std::function<void(const RunControl&)>;

std::vector<std::pair<const char*, Phase>> phases(const Mesh& mesh, const Bvh& tree, const MeshTopology& topology) {
    return {
        {"tree build", [&](const RunControl& c) { Bvh built(mesh, c); }},
        {"topology", [&](const RunControl& c) { MeshTopology built(mesh, c); }},
        {"mesh check", [&](const RunControl& c) { topology.check(mesh, tree, c); }},
        {"winding sign (crossing scan and fans)",
         [&](const RunControl& c) { insideByWinding(mesh, topology, makeGrid(mesh.worldBounds(), 48, 0.1), c); }},
    };
}

TEST(SetupPhases, ProgressNeverRunsBackwardsAndEndsAtOne) {
    const Mesh mesh = overlappingShells(5);
    const Bvh tree(mesh);
    const MeshTopology topology(mesh);
    for (const auto& [name, run] : phases(mesh, tree, topology)) {
        for (int threads : {1, 4}) {
            Watch watch;
            run(watch.control(threads));
            watch.expectMonotoneToOne(name);
        }
    }
}

TEST(SetupPhases, CancelStopsEachPhaseBeforeItEnds) {
    const Mesh mesh = overlappingShells(5);
    const Bvh tree(mesh);
    const MeshTopology topology(mesh);
    for (const auto& [name, run] : phases(mesh, tree, topology)) {
        Watch before; // raised before the phase starts
        before.cancel = true;
        EXPECT_THROW(run(before.control()), Cancelled) << name;
        Watch during; // raised by the phase's first progress report
        during.cancelAfter = 1;
        EXPECT_THROW(run(during.control(2)), Cancelled) << name;
        ASSERT_FALSE(during.reports.empty()) << name;
        EXPECT_LT(during.reports.back(), 1.0) << name << " ran to the end";
    }
}

TEST(SetupPhases, ModelHonoursCancelInItsTreeAndCheck) {
    const Mesh mesh = overlappingShells(4);
    Watch tree;
    tree.cancel = true;
    EXPECT_THROW(Model(mesh, tree.control()), Cancelled);
    Watch building;
    const Model model(mesh, building.control());
    building.expectMonotoneToOne("Model tree");
    Watch check;
    check.cancel = true;
    EXPECT_THROW(model.check(check.control()), Cancelled);
    // A cancelled check is not cached: the next one runs, with its own progress.
    Watch again;
    EXPECT_GT(model.check(again.control()).selfIntersections, 0u);
    again.expectMonotoneToOne("Model check");
}

} // namespace
} // namespace sdfgen
