#pragma once
// Which compiled copy of the SIMD kernels runs. Each stage's kernels (the nearest-triangle search
// and the rays in accel/, the exact distance in distance/, the fans in sign/) are compiled for
// AVX2 and for baseline x86-64 (SSE2), and the fans for AVX-512 too, all without fused
// multiply-adds, so that every copy gives the same bits; each stage keeps its own table of copies
// and runs the one for simdPath(). The paths are ordered: on a path for which a stage has no copy
// of its own, it runs its copy for the path before (AVX-512 runs the AVX2 copies but the fans').
// The path is chosen once per process from the CPU (the last it has); the environment variable
// SDFGEN_SIMD=baseline (or avx2, avx512) forces one, and setSimdPath does the same from code
// (tests, benchmarks).
namespace sdfgen {

enum class SimdPath { Baseline, Avx2, Avx512 };
constexpr SimdPath kSimdPaths[] = {SimdPath::Baseline, SimdPath::Avx2, SimdPath::Avx512};
const char* toString(SimdPath path);

// The path the kernels run now (chosen at first use when not set).
SimdPath simdPath();
// Whether this binary has the path and this CPU can run it.
bool simdPathAvailable(SimdPath path);
// Runs the kernels on `path` from now on; throws Error when it is not available. Not to be called
// while a kernel runs on another thread.
void setSimdPath(SimdPath path);

} // namespace sdfgen
