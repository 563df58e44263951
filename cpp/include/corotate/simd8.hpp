// Eight-float vectors for the hot loops GCC does not vectorise well by itself (a scatter of
// 3 x 3 blocks, 3 x 6 prolongator blocks), and eight-double ones for CG's vector operations
// (sums that GCC does not reorder by itself): GCC/Clang vector extensions, so each CPU clone
// (cpu_clones.hpp) compiles them with its own instructions (one 256-bit register with AVX2
// or AVX-512, two 128-bit ones on the x86-64 baseline). COROTATE_HAVE_FLOAT8 says whether the
// compiler has them; callers keep a scalar loop for the others.
//
// Every helper is inlined (COROTATE_CLONE_INLINE), so no call ever passes a Float8; GCC's
// -Wpsabi note that AVX vectors change the calling convention does not apply (silenced here,
// and in the .cpp files whose cloned functions use them).
#pragma once

#include <cstring>

#include "corotate/cpu_clones.hpp"

#if defined(__GNUC__)
#define COROTATE_HAVE_FLOAT8 1
#if !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace corotate::simd {

using Float8 = float __attribute__((vector_size(32)));

// From and to any address (unaligned).
COROTATE_CLONE_INLINE Float8 load8(const float* p) {
  Float8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
COROTATE_CLONE_INLINE void store8(float* p, Float8 v) { std::memcpy(p, &v, sizeof v); }
COROTATE_CLONE_INLINE void add8(float* p, Float8 v) { store8(p, load8(p) + v); }
// The sum of the eight entries (halves added first: three vector adds, no serial chain).
COROTATE_CLONE_INLINE float sum8(Float8 v) {
  using Float4 = float __attribute__((vector_size(16)));
  const Float4 h = __builtin_shufflevector(v, v, 0, 1, 2, 3) + __builtin_shufflevector(v, v, 4, 5, 6, 7);
  return (h[0] + h[2]) + (h[1] + h[3]);
}

using Double8 = double __attribute__((vector_size(64)));

COROTATE_CLONE_INLINE Double8 load8(const double* p) {
  Double8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
COROTATE_CLONE_INLINE void store8(double* p, Double8 v) { std::memcpy(p, &v, sizeof v); }
COROTATE_CLONE_INLINE double sum8(Double8 v) {
  using Double4 = double __attribute__((vector_size(32)));
  const Double4 h = __builtin_shufflevector(v, v, 0, 1, 2, 3) + __builtin_shufflevector(v, v, 4, 5, 6, 7);
  return (h[0] + h[2]) + (h[1] + h[3]);
}

// Four doubles: one AVX2 register. Eight-double vectors are right for AVX-512 only: in an AVX2
// clone GCC keeps them in memory and moves each half through general registers (the AVX2
// code path of CG's vector operations and of the supernodal factorization ran several times
// slower than with four-double vectors); code that runs on both picks by
// cpu_runs_avx512_clones() (cpu_clones.hpp) and is written over the vector type, with these.
using Double4 = double __attribute__((vector_size(32)));

template <class V>
COROTATE_CLONE_INLINE V load(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class V>
COROTATE_CLONE_INLINE void store(double* p, V v) {
  std::memcpy(p, &v, sizeof v);
}
COROTATE_CLONE_INLINE double sum(Double8 v) { return sum8(v); }
COROTATE_CLONE_INLINE double sum(Double4 v) { return (v[0] + v[2]) + (v[1] + v[3]); }

}  // namespace corotate::simd

#if !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#endif
