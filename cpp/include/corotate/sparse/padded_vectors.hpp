// Vectors padded to four entries per node, for the block-sparse products' vector kernels
// (BlockSparseMatrix::multiply_symmetric, SinglePrecisionSymmetric::multiply): a node's
// three values then load as one four-wide vector.
#pragma once

#include <cstring>
#include <vector>

#include "corotate/common.hpp"
#include "corotate/cpu_clones.hpp"

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
template <class Kernel>
void padded_product(const Vec& x, Vec& y, Kernel&& kernel, double scale = 1.0) {
  const Index n = x.size() / 3;
  thread_local std::vector<double> xpad, ypad;
  xpad.resize(4 * n);
  ypad.resize(4 * n);
  for (Index i = 0; i < n; ++i) {
    xpad[4 * i] = x[3 * i];
    xpad[4 * i + 1] = x[3 * i + 1];
    xpad[4 * i + 2] = x[3 * i + 2];
    xpad[4 * i + 3] = 0.0;
  }
  kernel(xpad.data(), ypad.data());
  for (Index i = 0; i < n; ++i) {
    y[3 * i] = scale * ypad[4 * i];
    y[3 * i + 1] = scale * ypad[4 * i + 1];
    y[3 * i + 2] = scale * ypad[4 * i + 2];
  }
}

}  // namespace corotate
