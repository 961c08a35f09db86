// The binary tree's build alone (core/accel/bvh.hpp): loads a mesh, builds its Bvh --repeat times on
// --threads threads, and prints the fastest and the median wall seconds and a checksum of the tree
// (every node's box, children, leaf range and split axis, the leaf order and the depth). Equal
// checksums: the same tree bit for bit, e.g. across versions of the build or thread counts.
#include "core/accel/bvh.hpp"
#include "sdfgen/mesh.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>

namespace {

struct Checksum {
    std::uint64_t value = 1469598103934665603ull; // FNV-1a
    template <class T>
    void add(const T& x) {
        unsigned char bytes[sizeof(T)];
        std::memcpy(bytes, &x, sizeof(T));
        for (unsigned char b : bytes) value = (value ^ b) * 1099511628211ull;
    }
};

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Time the binary tree's build alone (sdfgen's tree benchmark)"};
    std::string input;
    int repeat = 9, threads = 0;
    app.add_option("mesh", input, "A mesh file")->required();
    app.add_option("--threads", threads, "Worker threads, 0 for all cores")->capture_default_str();
    app.add_option("--repeat", repeat, "Builds; the fastest and the median are printed")->check(CLI::Range(1, 1000))->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        using namespace sdfgen;
        using Clock = std::chrono::steady_clock;
        const Mesh mesh = loadMesh(input);
        RunControl control;
        control.threads = threads;
        std::vector<double> seconds;
        for (int run = 0; run < repeat; ++run) {
            const auto start = Clock::now();
            const Bvh tree(mesh, control);
            seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
        }
        std::sort(seconds.begin(), seconds.end());
        const Bvh tree(mesh, control);
        Checksum checksum;
        std::vector<int> depths(tree.nodeCount(), 0); // children follow their parent
        int depth = 0;
        for (std::uint32_t i = 0; i < tree.nodeCount(); ++i) {
            const Bvh::NodeView n = tree.node(i);
            depth = std::max(depth, depths[i]);
            if (n.count == 0) depths[n.first] = depths[n.second] = depths[i] + 1;
            for (int a = 0; a < 3; ++a) checksum.add(n.box.min[a]), checksum.add(n.box.max[a]);
            checksum.add(n.first), checksum.add(n.second), checksum.add(n.count), checksum.add(n.axis), checksum.add(n.slot);
        }
        for (std::uint32_t t : tree.leafTriangles()) checksum.add(t);
        checksum.add(depth);
        std::printf("%s: %zu triangles, %zu nodes, depth %d, %d threads, %d builds: fastest %.4f s, median %.4f s, checksum %016llx\n",
                    input.c_str(), mesh.triangleCount(), tree.nodeCount(), depth, threads, repeat, seconds.front(),
                    seconds[seconds.size() / 2], (unsigned long long)checksum.value);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_tree: %s\n", e.what());
        return 1;
    }
}
