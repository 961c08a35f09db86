// The row count's AVX2 copy (see core/sign/row_count.hpp): compiled for AVX2 (core/simd/avx2_begin.inc).
#if defined(__x86_64__) || defined(__i386__)
#include "core/sign/row_count.hpp"

#include <immintrin.h>
#include <cstdint>
#include <vector>

#define SDFGEN_KERNEL_NAMESPACE avx2
#define SDFGEN_KERNEL_AVX2 1
#include "core/simd/avx2_begin.inc"
namespace sdfgen::rows::SDFGEN_KERNEL_NAMESPACE {
namespace simd {
using f8 = sdfgen::simd::f8;
using i8 = sdfgen::simd::i8;
} // namespace simd
#include "core/simd/simd_ops.inc"
#include "core/sign/row_count.inc"
} // namespace sdfgen::rows::SDFGEN_KERNEL_NAMESPACE
#include "core/simd/avx2_end.inc"
#endif
