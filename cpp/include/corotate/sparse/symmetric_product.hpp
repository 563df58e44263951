// The symmetric block product's kernel (symmetric_chunk), shared by the system matrix
// (BlockSparseMatrix::multiply_symmetric) and its float32 copy (SinglePrecisionSymmetric),
// with its four-wide vector helpers: x and y are padded to four entries per node
// (padded_product), so a node's three values load as one vector.
#pragma once

#include <algorithm>
#include <cstring>
#include <vector>

#include "corotate/common.hpp"
#include "corotate/cpu_clones.hpp"
#include "corotate/parallel.hpp"

namespace corotate {

// Four values of type T (double or float) from any address (unaligned), as a GCC vector
// type, so each CPU clone uses its own vector width. A block row loaded this way brings the
// next value along (the next row's first, or the next block's); it meets x's zero fourth
// entry, or lands in y's unused fourth.
template <class T>
struct Four {
  typedef T type __attribute__((vector_size(4 * sizeof(T))));
};
template <class T>
COROTATE_CLONE_INLINE typename Four<T>::type load4(const T* p) {
  typename Four<T>::type v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class V>
COROTATE_CLONE_INLINE auto sum3(V v) {
  return v[0] + v[1] + v[2];
}

// Where row i's blocks lie for symmetric_chunk, in the order they are read: [first[i],
// lower_end[i]) have columns in earlier row chunks, diagonal[i] is the diagonal block,
// (diagonal[i], chunk_end[i]) the upper blocks inside the row's chunk and [chunk_end[i],
// first[i + 1]) those after it.
struct SymmetricRows {
  const int* first;  // num_nodes + 1
  const int* lower_end;
  const int* diagonal;
  const int* chunk_end;
};

// y = A x on rows [first, last), one row chunk, for a symmetric A given by the blocks
// multiply_symmetric reads (9 values each, row-major, from values), x and y four per node,
// values, vectors and sums all of type T: double for the system matrix, float for its
// float32 copy. Within a chunk each upper pair is read once and used twice; a pair across
// chunks is read from both sides, so chunks write disjoint rows and run on separate threads,
// and the sums do not depend on the thread count. (The callers keep the parallel loop over
// chunks themselves: GCC outlines an OpenMP loop before inlining, so one inside this helper
// would not be compiled for the caller's CPU clone.)
template <class T>
COROTATE_CLONE_INLINE void symmetric_chunk(const T* values, const int* columns, const SymmetricRows& rows, int first,
                                           int last, const T* xp, T* yp) {
  using V = typename Four<T>::type;
  // y_i of the chunk collects B^T x_i from the chunk's earlier rows, then its own row.
  std::fill(yp + 4 * first, yp + 4 * last, T(0));
  for (int i = first; i < last; ++i) {
    const V xi = load4(xp + 4 * i);
    const V x0 = {xi[0], xi[0], xi[0], xi[0]}, x1 = {xi[1], xi[1], xi[1], xi[1]}, x2 = {xi[2], xi[2], xi[2], xi[2]};
    V a0 = {0, 0, 0, 0}, a1 = a0, a2 = a0;
    const int diagonal = rows.diagonal[i], chunk_end = rows.chunk_end[i], row_end = rows.first[i + 1];
    for (int k = rows.first[i]; k < rows.lower_end[i]; ++k) {  // pairs with earlier chunks
      const T* b = values + 9 * k;
      const V xj = load4(xp + 4 * columns[k]);
      a0 += load4(b) * xj;
      a1 += load4(b + 3) * xj;
      a2 += load4(b + 6) * xj;
    }
    {
      const T* b = values + 9 * diagonal;
      a0 += load4(b) * xi;
      a1 += load4(b + 3) * xi;
      const V last_row = {b[6], b[7], b[8], T(0)};  // the values may end here
      a2 += last_row * xi;
    }
    for (int k = diagonal + 1; k < chunk_end; ++k) {  // in-chunk pairs: both products
      const T* b = values + 9 * k;
      const int j = columns[k];
      const V xj = load4(xp + 4 * j);
      const V b0 = load4(b), b1 = load4(b + 3), b2 = load4(b + 6);
      a0 += b0 * xj;
      a1 += b1 * xj;
      a2 += b2 * xj;
      V yj = load4(yp + 4 * j);
      yj += b0 * x0 + b1 * x1 + b2 * x2;
      std::memcpy(yp + 4 * j, &yj, sizeof yj);
    }
    for (int k = chunk_end; k < row_end; ++k) {  // pairs with later chunks
      const T* b = values + 9 * k;
      const V xj = load4(xp + 4 * columns[k]);
      a0 += load4(b) * xj;
      a1 += load4(b + 3) * xj;
      a2 += load4(b + 6) * xj;
    }
    yp[4 * i] += sum3(a0);
    yp[4 * i + 1] += sum3(a1);
    yp[4 * i + 2] += sum3(a2);
  }
}

// Below this many nodes padded_product's copies stay on one thread (a fork costs microseconds).
inline constexpr Index kParallelCopyNodes = 8192;

// y = scale * (kernel applied to x): x is copied to four entries per node (the fourth zero),
// kernel(x4, y4) fills y4 likewise, and its first three per node, times scale, go to y. Work
// buffers per thread and per kernel type, allocated once.
template <class Pad = double, class Kernel>
void padded_product(const Vec& x, Vec& y, Kernel&& kernel, double scale = 1.0) {
  const Index n = x.size() / 3;
  thread_local std::vector<Pad> xpad, ypad;
  xpad.resize(4 * n);
  ypad.resize(4 * n);
  // The copies are a third of a product's memory traffic at 122,880 tets: threaded with it.
  Pad* xp = xpad.data();
  const double* xs = x.data();
  parallel_for(n, n >= kParallelCopyNodes, [&](Index i) {
    xp[4 * i] = Pad(xs[3 * i]);
    xp[4 * i + 1] = Pad(xs[3 * i + 1]);
    xp[4 * i + 2] = Pad(xs[3 * i + 2]);
    xp[4 * i + 3] = Pad(0);
  });
  kernel(xpad.data(), ypad.data());
  const Pad* yp = ypad.data();
  double* ys = y.data();
  parallel_for(n, n >= kParallelCopyNodes, [&](Index i) {
    ys[3 * i] = scale * yp[4 * i];
    ys[3 * i + 1] = scale * yp[4 * i + 1];
    ys[3 * i + 2] = scale * yp[4 * i + 2];
  });
}

}  // namespace corotate
