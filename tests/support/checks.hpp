#pragma once
// Test helpers shared by the suites: error messages, and a scratch folder per test.
#include "sdfgen/error.hpp"
#include "core/bake/bake.hpp"
#include "core/accel/bvh.hpp"

#include <gtest/gtest.h>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

// Defined in a build under AddressSanitizer, whose allocator and shadow memory some tests must allow for.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SDFGEN_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define SDFGEN_TEST_ASAN 1
#endif

#define EXPECT_CONTAINS(text, part)                                                                  \
    EXPECT_NE(std::string(text).find(part), std::string::npos)                                       \
        << "expected to find '" << (part) << "' in '" << (text) << "'"

namespace sdfgen::test {

// The message of the sdfgen::Error that f throws; a test failure when it throws nothing or another type.
template <class F>
std::string errorFrom(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected sdfgen::Error, got another exception: " << e.what();
        return "";
    }
    ADD_FAILURE() << "expected sdfgen::Error, nothing was thrown";
    return "";
}

// Bakes `mesh` with `settings` on `threads` threads (0 = all), building its tree.
inline BakeResult bakeMesh(const Mesh& mesh, const BakeSettings& settings, int threads = 0) {
    const Bvh tree(mesh);
    RunControl control;
    control.threads = threads;
    return bake(mesh, tree, settings, control);
}

// Every sample position of `grid` in index order (x fastest), x y z interleaved: point queries at
// these give the baked values.
inline std::vector<double> samplePositions(const Grid& grid) {
    std::vector<double> xyz;
    xyz.reserve(3 * grid.sampleCount());
    for (int k = 0; k < grid.dims.z; ++k) {
        for (int j = 0; j < grid.dims.y; ++j) {
            for (int i = 0; i < grid.dims.x; ++i) {
                const glm::dvec3 p = grid.position(i, j, k);
                xyz.insert(xyz.end(), {p.x, p.y, p.z});
            }
        }
    }
    return xyz;
}

// A fixture with a fresh folder under the system temp folder for each test, removed afterwards.
class ScratchFolderTest : public ::testing::Test {
protected:
    void SetUp() override {
        static std::atomic<int> counter{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = std::filesystem::temp_directory_path() /
               ("sdfgen-test-" + std::string(info->test_suite_name()) + "-" + std::string(info->name()) + "-" +
                std::to_string(getpid()) + "-" + std::to_string(counter++));
        std::filesystem::remove_all(dir_);
        ASSERT_TRUE(std::filesystem::create_directories(dir_));
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }

    // Writes `contents` to a file in the folder and returns its path.
    std::string write(const std::string& name, const std::string& contents) {
        const std::filesystem::path path = dir_ / name;
        std::ofstream out(path, std::ios::binary);
        out << contents;
        EXPECT_TRUE(out.good());
        return path.string();
    }

    std::filesystem::path dir_;
};

} // namespace sdfgen::test
