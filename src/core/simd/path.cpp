#include "core/simd/path.hpp"
#include "sdfgen/error.hpp"

#include <atomic>
#include <cstdlib>
#include <string>

namespace sdfgen {

namespace {

bool runs(SimdPath path) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init(); // in case the first use runs in another library's static constructor
    if (path == SimdPath::Avx2) return __builtin_cpu_supports("avx2");
    if (path == SimdPath::Avx512) {
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
    }
#endif
    return path == SimdPath::Baseline;
}

// The last path the CPU has, unless SDFGEN_SIMD names one (an unknown or unavailable one is an
// error at first use, not silently another path).
SimdPath choosePath() {
    const char* forced = std::getenv("SDFGEN_SIMD");
    if (forced && *forced) {
        const std::string name = forced;
        for (SimdPath path : kSimdPaths) {
            if (name == toString(path) && runs(path)) return path;
        }
        throw Error("SDFGEN_SIMD=" + name + ": not a SIMD path this binary and CPU can run (baseline, avx2 or avx512)");
    }
    SimdPath best = SimdPath::Baseline;
    for (SimdPath path : kSimdPaths) {
        if (runs(path)) best = path;
    }
    return best;
}

constexpr int kUnset = -1;
std::atomic<int> chosen{kUnset};

} // namespace

const char* toString(SimdPath path) {
    switch (path) {
    case SimdPath::Avx2: return "avx2";
    case SimdPath::Avx512: return "avx512";
    default: return "baseline";
    }
}

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
