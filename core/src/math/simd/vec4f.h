// A four-float SIMD vector with the few operations the engine's kernels need, chosen at build
// time by LDSM_SIMD (CMake defines LDSM_SIMD_SSE, LDSM_SIMD_NEON or LDSM_SIMD_SCALAR):
//   Vec4 = Vec4Sse (SSE2) | Vec4Neon (AArch64 / ARMv7 NEON) | Vec4Scalar (plain C++).
// Kernels are templates over the vector type, so tests can run the plain-C++ version next to
// the selected one. Every type V provides:
//   V::load(p) (16-byte aligned), V::loadu(p), V::loadInt16(p) (four int16 as floats), V::set1(x),
//   V::setLanes(a, b, c, d) (lane 0 = a; for values loaded one by one: writing them to an array
//   and loading that as a vector cannot take the stores' values and waits until they are
//   written), V::zero(), v.store(p), v.storeu(p),
//   v.storeInt16(p) (lanes holding integers within the int16 range, stored as four int16);
//   + - * / ; comparisons < > >= giving V::Mask, Mask & Mask, allOf(mask), laneBits(mask) (bit i
//   set when lane i is true), select(mask, a, b); squareRoot, absolute, maximum (of lanes that are
//   not NaN), truncate(v, ints) (towards zero, also stored as int32), shiftDown1 (a1 a2 a3 0),
//   broadcast<K>, transpose4(a, b, c, d), sum4(a, b, c, d) = (sum a, .., sum d), horizontalSum.
#pragma once

#include "math/simd/vec4f_scalar.h"

#if defined(LDSM_SIMD_SSE)
#if !defined(__SSE2__)
#error "LDSM_SIMD=sse needs SSE2"
#endif
#include "math/simd/vec4f_sse.h"
#elif defined(LDSM_SIMD_NEON)
#if !defined(__ARM_NEON) && !defined(__ARM_NEON__)
#error "LDSM_SIMD=neon needs NEON (e.g. -mfpu=neon on ARMv7)"
#endif
#include "math/simd/vec4f_neon.h"
#endif

// Fully unrolls the next (short, constant-trip) loop: the kernels' triangular loops must become
// straight-line code so that the Jacobian rows stay in registers.
#if defined(__clang__)
#define LDSM_SIMD_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define LDSM_SIMD_UNROLL _Pragma("GCC unroll 16")
#else
#define LDSM_SIMD_UNROLL
#endif

namespace ldsm {
namespace simd {

#if defined(LDSM_SIMD_SSE)
using Vec4 = Vec4Sse;
constexpr const char* kSimdName = "sse";
#elif defined(LDSM_SIMD_NEON)
using Vec4 = Vec4Neon;
constexpr const char* kSimdName = "neon";
#else
using Vec4 = Vec4Scalar;
constexpr const char* kSimdName = "scalar";
#endif

}  // namespace simd
}  // namespace ldsm
