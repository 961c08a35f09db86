#include "core/simd/path.hpp"
#include "sdfgen/error.hpp"

#include <atomic>
#include <cstdlib>
#include <string>

namespace sdfgen {

namespace {

bool runs(SimdPath path) {
#if defined(__x86_64__) || defined(__i386__)
    if (path == SimdPath::Avx2) {
        __builtin_cpu_init(); // in case the first use runs in another library's static constructor
        return __builtin_cpu_supports("avx2");
    }
#endif
    return path == SimdPath::Baseline;
}

// AVX2 where the CPU has it, unless SDFGEN_SIMD names a path (an unknown or unavailable one is
// an error at first use, not silently another path).
SimdPath choosePath() {
    const char* forced = std::getenv("SDFGEN_SIMD");
    if (forced && *forced) {
        const std::string name = forced;
        if (name == "baseline" && runs(SimdPath::Baseline)) return SimdPath::Baseline;
        if (name == "avx2" && runs(SimdPath::Avx2)) return SimdPath::Avx2;
        throw Error("SDFGEN_SIMD=" + name + ": not a SIMD path this binary and CPU can run (baseline or avx2)");
    }
    return runs(SimdPath::Avx2) ? SimdPath::Avx2 : SimdPath::Baseline;
}

constexpr int kUnset = -1;
std::atomic<int> chosen{kUnset};

} // namespace

const char* toString(SimdPath path) { return path == SimdPath::Avx2 ? "avx2" : "baseline"; }

bool simdPathAvailable(SimdPath path) { return runs(path); }

void setSimdPath(SimdPath path) {
    if (!runs(path)) throw Error(std::string("SIMD path ") + toString(path) + " is not available on this CPU or in this binary");
    chosen.store(int(path));
}

SimdPath simdPath() {
    int path = chosen.load(std::memory_order_acquire);
    if (path == kUnset) {
        static const int first = int(choosePath());
        int expected = kUnset;
        chosen.compare_exchange_strong(expected, first);
        path = chosen.load();
    }
    return SimdPath(path);
}

} // namespace sdfgen
