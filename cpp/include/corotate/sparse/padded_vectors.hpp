// Vectors padded to four entries per node, for the block-sparse products' vector kernels
// (BlockSparseMatrix::multiply_symmetric, SinglePrecisionSymmetric::multiply): a node's
// three values then load as one four-wide vector.
#pragma once

#include <cstring>
#include <vector>

#include "corotate/common.hpp"
#include "corotate/cpu_clones.hpp"
#include "corotate/parallel.hpp"

namespace corotate {

// Four doubles from any address (unaligned); a GCC vector type, so each CPU clone uses its
// own vector width. A block row loaded this way brings the next value along (the next row's
// first, or the next block's); it meets x's zero fourth entry, or lands in y's unused fourth.
typedef double v4d __attribute__((vector_size(32)));
COROTATE_CLONE_INLINE v4d load4(const double* p) {
  v4d v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// The same from four floats, widened to double.
typedef float v4f __attribute__((vector_size(16)));
COROTATE_CLONE_INLINE v4d load4(const float* p) {
  v4f v;
  std::memcpy(&v, p, sizeof v);
  return __builtin_convertvector(v, v4d);
}
COROTATE_CLONE_INLINE double sum3(v4d v) { return v[0] + v[1] + v[2]; }

// y = scale * (kernel applied to x): x is copied to four entries per node (the fourth zero),
// kernel(x4, y4) fills y4 likewise, and its first three per node, times scale, go to y. Work
// buffers per thread and per kernel type, allocated once.
// Below this many nodes the copies stay on one thread (a fork costs microseconds).
inline constexpr Index kParallelCopyNodes = 8192;

template <class Kernel>
void padded_product(const Vec& x, Vec& y, Kernel&& kernel, double scale = 1.0) {
  const Index n = x.size() / 3;
  thread_local std::vector<double> xpad, ypad;
  xpad.resize(4 * n);
  ypad.resize(4 * n);
  // The copies are a third of a product's memory traffic at 122,880 tets: threaded with it.
  double* xp = xpad.data();
  const double* xs = x.data();
  COROTATE_PARALLEL_FOR(n >= kParallelCopyNodes)
  for (Index i = 0; i < n; ++i) {
    xp[4 * i] = xs[3 * i];
    xp[4 * i + 1] = xs[3 * i + 1];
    xp[4 * i + 2] = xs[3 * i + 2];
    xp[4 * i + 3] = 0.0;
  }
  kernel(xpad.data(), ypad.data());
  const double* yp = ypad.data();
  double* ys = y.data();
  COROTATE_PARALLEL_FOR(n >= kParallelCopyNodes)
  for (Index i = 0; i < n; ++i) {
    ys[3 * i] = scale * yp[4 * i];
    ys[3 * i + 1] = scale * yp[4 * i + 1];
    ys[3 * i + 2] = scale * yp[4 * i + 2];
  }
}

}  // namespace corotate
