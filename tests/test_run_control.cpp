// The control path: a RunControl given to Model's construction reaches the tree build (threads,
// cancel, progress), bad thread counts are refused, warnings reach RunControl::warn; the cgroup
// memory reader on fake cgroup trees; memory checks and messages that name the mesh; large
// buffers on transparent huge pages.
#include "core/runtime/memory.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/model.hpp"
#include "sdfgen/sample.hpp"

#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>

namespace sdfgen {
namespace {

using test::errorFrom;
namespace fs = std::filesystem;

TEST(RunControlPath, CancelledBeforeConstructionThrowsAtOnce) {
    std::atomic<bool> cancel{true};
    RunControl control;
    control.cancel = &cancel;
    Mesh sphere = test::icosphere(1.0f, 6); // 82k triangles: a tree build that takes a while
    const auto start = std::chrono::steady_clock::now();
    EXPECT_THROW(Model(std::move(sphere), control), Cancelled);
    // Nothing is read either: the cancel flag is checked before the load.
    EXPECT_THROW(Model::load("/nonexistent/mesh.obj", control), Cancelled);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
}

TEST(RunControlPath, TreeBuildStopsWhenCancelled) {
    std::atomic<bool> cancel{false};
    std::atomic<int> reports{0};
    RunControl control;
    control.cancel = &cancel;
    // The first progress report of the tree build raises the flag: the build must notice it.
    control.progress = [&](double fraction) {
        if (fraction < 1.0) {
            ++reports;
            cancel = true;
        }
    };
    EXPECT_THROW(Model(test::icosphere(1.0f, 5), control), Cancelled);
    EXPECT_GT(reports.load(), 0);
}

TEST(RunControlPath, TreeBuildRunsOnTheGivenThreads) {
    for (const int threads : {1, 3}) {
        std::mutex mutex;
        std::set<int> seen; // the concurrency of the arenas the build reports from
        RunControl control;
        control.threads = threads;
        control.progress = [&](double fraction) {
            if (fraction >= 1.0) return; // the final report comes from the calling thread
            std::lock_guard<std::mutex> lock(mutex);
            seen.insert(tbb::this_task_arena::max_concurrency());
        };
        const Model model(test::icosphere(1.0f, 5), control);
        EXPECT_EQ(seen, std::set<int>{threads}) << threads << " threads";
    }
}

TEST(RunControlPath, ThreadCountsBeyondTheLimitAreErrors) {
    for (const int threads : {-1, kMaxThreads + 1, 100000}) {
        RunControl control;
        control.threads = threads;
        EXPECT_CONTAINS(errorFrom([&] { Model(test::icosphere(1.0f, 1), control); }), "threads must be from 0 (all cores) to 1024");
    }
    const Model model(test::icosphere(1.0f, 1));
    RunControl control;
    control.threads = 100000;
    EXPECT_CONTAINS(errorFrom([&] { model.bake(BakeSettings{}, control); }), "threads must be");
    EXPECT_CONTAINS(errorFrom([&] { model.signedDistance({glm::dvec3(0.0)}, control); }), "threads must be");
    EXPECT_CONTAINS(errorFrom([&] { sampleSdf(model, 10, SampleSettings{}, control); }), "threads must be");
    control.threads = kMaxThreads; // the limit itself is allowed
    EXPECT_EQ(model.signedDistance({glm::dvec3(0.0)}, control).size(), 1u);
}

TEST(RunControlPath, WarningsReachTheControl) {
    std::vector<std::string> warned;
    RunControl control;
    control.warn = [&](const std::string& warning) { warned.push_back(warning); };
    // Two zero-area triangles beside a tetrahedron: buildMesh drops them, the construction says so.
    const Mesh mesh = buildMesh("degenerate.obj", std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                                {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {1, 1, 2}, {0, 0, 1}});
    const Model model(mesh, control);
    EXPECT_NE(std::find(warned.begin(), warned.end(), "degenerate.obj: dropped 2 zero-area triangles"), warned.end());

    // A bake's warnings reach it too, naming the mesh: here an explicit pseudonormal sign on a mesh
    // inside out as a whole.
    Mesh inverted = test::box(glm::vec3(1.0f));
    for (glm::uvec3& t : inverted.triangles) std::swap(t.y, t.z);
    inverted = buildMesh("inverted.obj", inverted.worldPositions(), inverted.triangles);
    warned.clear();
    const Model insideOut(inverted, control);
    BakeSettings settings;
    settings.res = 8;
    settings.sign = SignMethod::Pseudonormal;
    const BakeResult result = insideOut.bake(settings, control);
    ASSERT_FALSE(result.warnings.empty());
    ASSERT_EQ(warned.size(), result.warnings.size());
    for (std::size_t i = 0; i < warned.size(); ++i) EXPECT_EQ(warned[i], "inverted.obj: " + result.warnings[i]);
}

TEST(RunControlPath, HugeMeshErrorNamesTheMeshAndItsExtent) {
    const Mesh huge = buildMesh("huge.obj", std::vector<glm::dvec3>{{-1e307, 0, 0}, {1e307, 0, 0}, {0, 1e307, 0}, {0, 0, 1e307}},
                                {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
    const std::string message = errorFrom([&] { Model(huge).bake(BakeSettings{}); });
    EXPECT_CONTAINS(message, "huge.obj: the mesh is 2e+307 across; with padding 0.1 its grid would be 2.4e+307 across");
}

TEST(RunControlPath, SamplesAreCheckedAgainstMemoryBeforeAllocating) {
    const Model model(test::icosphere(1.0f, 1));
    // 2^40 samples need 52 TiB: refused at once, before any allocation.
    const std::string message = errorFrom([&] { sampleSdf(model, std::size_t(1) << 40, SampleSettings{}); });
    EXPECT_CONTAINS(message, "1099511627776 samples need about 54525952 MiB but only");
}

class CgroupMemoryTest : public test::ScratchFolderTest {
protected:
    // Writes `text` to root/relative, creating folders.
    void put(const std::string& relative, const std::string& text) {
        fs::create_directories((dir_ / "root" / relative).parent_path());
        write("root/" + relative, text);
    }
    CgroupMemory read(const std::string& cgroupLines) {
        write("cgroup", cgroupLines);
        return cgroupMemory((dir_ / "cgroup").string(), (dir_ / "root").string());
    }
};

TEST_F(CgroupMemoryTest, V2WalksUpTheProcessGroup) {
    put("cgroup.controllers", "memory\n");
    put("job/step/task/memory.max", "max\n");
    put("job/step/task/memory.current", "100\n");
    put("job/memory.max", "1000\n"); // a Slurm job's limit, two levels up
    put("job/memory.current", "300\n");
    put("memory.max", "5000\n");
    CgroupMemory m = read("0::/job/step/task\n");
    EXPECT_EQ(m.limit, 1000u);
    EXPECT_EQ(m.room, 700u);
    put("job/step/task/memory.max", "500\n"); // a tighter one below, nearly used up
    put("job/step/task/memory.current", "450\n");
    m = read("0::/job/step/task\n");
    EXPECT_EQ(m.limit, 500u);
    EXPECT_EQ(m.room, 50u);
}

TEST_F(CgroupMemoryTest, V1AndHybridAndContainers) {
    put("memory/slurm/uid/job/memory.limit_in_bytes", "2000\n");
    put("memory/slurm/uid/job/memory.usage_in_bytes", "1500\n");
    put("memory/memory.limit_in_bytes", "9223372036854771712\n"); // v1's "no limit"
    put("unified/memory.max", "max\n");
    CgroupMemory m = read("9:cpu,memory:/slurm/uid/job\n0::/\n");
    EXPECT_EQ(m.limit, 2000u);
    EXPECT_EQ(m.room, 500u);
    // A container whose group's path does not exist below the mount: the mount's root holds its limit.
    m = read("4:memory:/docker/abcdef\n");
    EXPECT_EQ(m.limit, 9223372036854771712u);
    // No memory controller, unreadable files, no file at all: no limit.
    m = read("3:cpuset:/\n");
    EXPECT_EQ(m.limit, UINT64_MAX);
    EXPECT_EQ(m.room, UINT64_MAX);
    m = cgroupMemory((dir_ / "missing").string(), (dir_ / "root").string());
    EXPECT_EQ(m.limit, UINT64_MAX);
}

// The VmFlags of the mapping that holds `address` (/proc/self/smaps), or "" where none does.
std::string mappingFlags(std::uintptr_t address) {
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool holds = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream range(line);
        if (range >> std::hex >> lo >> dash >> hi && dash == '-') {
            holds = lo <= address && address < hi;
        } else if (holds && line.rfind("VmFlags:", 0) == 0) {
            return line + " ";
        }
    }
    return "";
}

TEST(HugePages, LargeZeroFilledBuffersAskForThem) {
    if (!fs::exists("/sys/kernel/mm/transparent_hugepage/enabled")) GTEST_SKIP() << "no transparent huge pages in this kernel";
    constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
    auto firstHugePage = [&](const void* data) { return (std::uintptr_t(data) + kHugePage - 1) / kHugePage * kHugePage; };
    std::vector<float> large, small;
    zeroFilled(large, kHugePagesFrom / sizeof(float) + 1, RunControl{});
    EXPECT_CONTAINS(mappingFlags(firstHugePage(large.data())), " hg ");
    EXPECT_TRUE(std::all_of(large.begin(), large.end(), [](float v) { return v == 0.0f; }));
    // Below the threshold a buffer is left as it is (the heap's blocks are reused again and again).
    zeroFilled(small, kHugePagesFrom / sizeof(float) / 2, RunControl{});
    EXPECT_EQ(mappingFlags(firstHugePage(small.data())).find(" hg "), std::string::npos);
}

} // namespace
} // namespace sdfgen
