// The nearest-triangle search's and the packet fill's AVX2 copies (see core/accel/wide_bvh.hpp): compiled for AVX2
// (core/simd/avx2_begin.inc).
#if defined(__x86_64__) || defined(__i386__)
#include "core/accel/wide_bvh.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <vector>

#define SDFGEN_KERNEL_NAMESPACE avx2
#define SDFGEN_KERNEL_AVX2 1
#include "core/simd/avx2_begin.inc"
namespace sdfgen::wide::SDFGEN_KERNEL_NAMESPACE {
namespace simd {
using f8 = sdfgen::simd::f8;
using i8 = sdfgen::simd::i8;
} // namespace simd
#include "core/simd/simd_ops.inc"
#include "core/accel/packet_ops.inc"
#include "core/accel/wide_nearest.inc"
#include "core/accel/wide_fill.inc"
} // namespace sdfgen::wide::SDFGEN_KERNEL_NAMESPACE
#include "core/simd/avx2_end.inc"
#endif
