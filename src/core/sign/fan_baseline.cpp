// The fan kernel's baseline copy (see core/sign/fan_kernel.inc): compiled with the flags of the build
// (x86-64's SSE2 unless SDFGEN_NATIVE), for CPUs without AVX2 and for checking the AVX2 copy.
#include "core/sign/fan_kernel.hpp"
#include "core/sign/winding_sign.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#define SDFGEN_KERNEL_NAMESPACE baseline
#include "core/sign/fan_kernel.inc"
