// dense_kernels.hpp, compiled per instruction-set level (COROTATE_CPU_CLONES). The product
// U -= B B^T holds most of the flops: a register tile of 16 rows by 4 columns of U is summed in
// eight eight-double vectors over all of B's columns, then subtracted once. The panel's
// triangular solve runs over chunks of rows small enough to stay in the first-level cache.
#include "corotate/solvers/dense_kernels.hpp"

#include <algorithm>
#include <cmath>

#include "corotate/simd8.hpp"

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace corotate {

namespace {

constexpr int kChunkRows = 64;  // rows of the triangular solve per pass (64 x k doubles in L1)

}  // namespace

COROTATE_CPU_CLONES bool factor_panel(double* panel, int m, int k) {
  // The diagonal block, column by column (right-looking): k is at most a few hundred.
  for (int j = 0; j < k; ++j) {
    double* col = panel + static_cast<size_t>(j) * m;
    const double d = col[j];
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double l = std::sqrt(d), inv = 1.0 / l;
    col[j] = l;
    for (int r = j + 1; r < k; ++r) col[r] *= inv;
    for (int c = j + 1; c < k; ++c) {
      double* target = panel + static_cast<size_t>(c) * m;
      const double f = col[c];
      for (int r = c; r < k; ++r) target[r] -= f * col[r];
    }
  }
  // The rows below: L21 = P21 L11^-T, chunk by chunk of rows.
  for (int r0 = k; r0 < m; r0 += kChunkRows) {
    const int rows = std::min(kChunkRows, m - r0);
    for (int j = 0; j < k; ++j) {
      double* col = panel + static_cast<size_t>(j) * m + r0;
      const double inv = 1.0 / panel[static_cast<size_t>(j) * m + j];
      for (int r = 0; r < rows; ++r) col[r] *= inv;
      for (int c = j + 1; c < k; ++c) {
        double* target = panel + static_cast<size_t>(c) * m + r0;
        const double f = panel[static_cast<size_t>(j) * m + c];
        for (int r = 0; r < rows; ++r) target[r] -= f * col[r];
      }
    }
  }
  return true;
}

namespace {

// Rows [i, i + count) of a column, count <= 8, as one vector (zeros beyond).
COROTATE_CLONE_INLINE simd::Double8 load_rows(const double* column, int count) {
  if (count == 8) return simd::load8(column);
  double v[8] = {};
  std::copy(column, column + count, v);
  return simd::load8(v);
}

COROTATE_CLONE_INLINE void subtract_rows(double* column, simd::Double8 value, int count) {
  if (count == 8) return simd::store8(column, simd::load8(column) - value);
  for (int r = 0; r < count; ++r) column[r] -= value[r];
}

// Rows [i, i + 8 * V) (the last vector cut at `rows`) of columns [j, j + nc) of U -= B B^T.
template <int V, int NR>
COROTATE_CLONE_INLINE void update_tile(const double* B, int ldb, int k, int i, int rows, int j, int nc, double* U,
                                       int ldu) {
  simd::Double8 acc[V][NR] = {};
  const int last = std::min(8, rows - i - 8 * (V - 1));
  for (int p = 0; p < k; ++p) {
    const double* column = B + static_cast<size_t>(p) * ldb;
    simd::Double8 a[V];
    for (int v = 0; v < V; ++v)
      a[v] = v + 1 < V ? simd::load8(column + i + 8 * v) : load_rows(column + i + 8 * v, last);
    for (int c = 0; c < NR; ++c) {
      const double w = c < nc ? column[j + c] : 0.0;
      for (int v = 0; v < V; ++v) acc[v][c] += a[v] * w;
    }
  }
  for (int c = 0; c < nc; ++c)
    for (int v = 0; v < V; ++v)
      subtract_rows(U + static_cast<size_t>(j + c) * ldu + i + 8 * v, acc[v][c], v + 1 < V ? 8 : last);
}

}  // namespace

COROTATE_CPU_CLONES void subtract_lower_product(const double* B, int ldb, int b, int k, double* U) {
  constexpr int NR = 4;
  for (int j = 0; j < b; j += NR) {
    const int nc = std::min(NR, b - j);
    // From the tile's first column down: the lower triangle and a sliver of the upper one,
    // which nothing reads.
    int i = j;
    for (; i + 16 <= b; i += 16) update_tile<2, NR>(B, ldb, k, i, b, j, nc, U, b);
    for (; i < b; i += 8) update_tile<1, NR>(B, ldb, k, i, b, j, nc, U, b);
  }
}

}  // namespace corotate
