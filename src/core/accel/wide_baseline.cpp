// The nearest-triangle search's and the packet fill's baseline copies (see core/accel/wide_bvh.hpp): compiled with the flags of
// the build (x86-64's SSE2 unless SDFGEN_NATIVE), for CPUs without AVX2 and for checking the AVX2 copy.
#include "core/accel/wide_bvh.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <vector>

#define SDFGEN_KERNEL_NAMESPACE baseline
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
