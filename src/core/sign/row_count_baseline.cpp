// The row count's baseline copy (see core/sign/row_count.hpp): compiled with the flags of the build
// (x86-64's SSE2 unless SDFGEN_NATIVE), for CPUs without AVX2 and for checking the AVX2 copy.
#include "core/sign/row_count.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif
#include <cstdint>
#include <vector>

#define SDFGEN_KERNEL_NAMESPACE baseline
namespace sdfgen::rows::SDFGEN_KERNEL_NAMESPACE {
namespace simd {
using f8 = sdfgen::simd::f8;
using i8 = sdfgen::simd::i8;
} // namespace simd
#include "core/simd/simd_ops.inc"
#include "core/sign/row_count.inc"
} // namespace sdfgen::rows::SDFGEN_KERNEL_NAMESPACE
