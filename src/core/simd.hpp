#pragma once
// Eight-lane float/int vectors written with the GCC/Clang vector extension: with AVX enabled
// (-march=native on any recent x86) each operation is one instruction, elsewhere the compiler
// lowers it to narrower vectors. The same templates also accept plain float, so one routine
// serves both a single ray and a packet.
#include <cstdint>
#ifdef __AVX__
#include <immintrin.h>
#endif

namespace sdfgen::simd {

using f8 = float __attribute__((vector_size(32)));
using i8 = std::int32_t __attribute__((vector_size(32)));

inline f8 splat(float x) { return f8{} + x; }
inline i8 splat(std::int32_t x) { return i8{} + x; }

inline f8 min(f8 a, f8 b) { return a < b ? a : b; }
inline f8 max(f8 a, f8 b) { return a > b ? a : b; }
inline float min(float a, float b) { return a < b ? a : b; }
inline float max(float a, float b) { return a > b ? a : b; }

// Lane-wise select: mask lanes are all ones (true) or zero.
inline f8 select(i8 mask, f8 a, f8 b) { return mask ? a : b; }
inline i8 select(i8 mask, i8 a, i8 b) { return mask ? a : b; }
inline float select(bool mask, float a, float b) { return mask ? a : b; }

// Whether any lane is set (masks are all ones or zero per lane): one movemask with AVX, else an OR
// over the lanes.
inline bool any(i8 mask) {
#ifdef __AVX__
    return _mm256_movemask_ps(_mm256_castsi256_ps(__m256i(mask))) != 0;
#else
    std::int32_t bits = 0;
    for (int lane = 0; lane < 8; ++lane) bits |= mask[lane];
    return bits != 0;
#endif
}
inline bool any(bool mask) { return mask; }

} // namespace sdfgen::simd
