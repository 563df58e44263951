// dense_kernels.hpp, compiled per instruction-set level (COROTATE_CPU_CLONES).
//
// Nearly all the flops are products C -= A W^T: the update matrix of each supernode and the
// trailing updates of the blocked panel factorization. They are blocked as fast dense
// products are (Goto's scheme): a slice of kKc of the inner dimension at a time, W's slice
// packed into panels of kNr columns and A's into panels of kMr rows, each contiguous in the
// order the register tile reads it; the tile (16 rows by 4 columns of C, eight eight-double
// vectors) sums over the slice in registers and is subtracted once. Without packing, the
// tile read its operands from kKc columns a panel's height apart, and the factorization ran
// at 6-8 GFlop/s on the 122,880-tet beam's large supernodes (Zen 4); packed, it runs at
// several times that (bench/README.md).
#include "corotate/solvers/dense_kernels.hpp"

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "corotate/cpu_clones.hpp"
#include "corotate/simd8.hpp"

namespace corotate {

namespace {

constexpr int kMr = 16;         // rows of the register tile (two eight-double vectors)
constexpr int kNr = 4;          // its columns
constexpr int kKc = 256;        // inner-dimension slice: a packed A panel (kMr x kKc) stays in L1
constexpr int kMc = 128;        // rows of A packed at a time (kMc x kKc doubles: 256 KB, in L2)
constexpr int kBlock = 48;      // columns per step of the blocked panel factorization
constexpr int kChunkRows = 64;  // rows per pass of the small triangular solves (in L1)

// Packing buffers, grown on first use (the factorization's sizes are bounded by kKc, kMc and
// the largest panel), one set per thread.
thread_local std::vector<double> packed_a, packed_w;

// C (rows x cols, leading dimension ldc) -= the sums of a register tile of kMr rows and
// Cols of w's kNr columns (w read with stride kNr), in vectors V; rows <= kMr, cols <= Cols.
template <class V, int Cols>
COROTATE_CLONE_INLINE void tile_columns(const double* a, const double* w, int kc, double* C, int ldc, int rows,
                                        int cols) {
  constexpr int kLanes = sizeof(V) / sizeof(double), kParts = kMr / kLanes;
  V acc[kParts][Cols] = {};
  for (int p = 0; p < kc; ++p) {
    V ap[kParts];
    for (int q = 0; q < kParts; ++q) ap[q] = simd::load<V>(a + kMr * p + kLanes * q);
    const double* wp = w + kNr * p;
    for (int c = 0; c < Cols; ++c) {
      const double wc = wp[c];
      for (int q = 0; q < kParts; ++q) acc[q][c] += ap[q] * wc;
    }
  }
  for (int c = 0; c < cols; ++c) {
    double* column = C + static_cast<size_t>(c) * ldc;
    if (rows == kMr) {
      for (int q = 0; q < kParts; ++q)
        simd::store<V>(column + kLanes * q, simd::load<V>(column + kLanes * q) - acc[q][c]);
    } else {
      for (int r = 0; r < rows; ++r) column[r] -= acc[r / kLanes][c][r % kLanes];
    }
  }
}

// C (rows x cols) -= the register tile's sums; rows <= kMr, cols <= kNr.
COROTATE_CLONE_INLINE void tile(const double* a, const double* w, int kc, double* C, int ldc, int rows, int cols,
                                bool wide) {
  constexpr int kHalf = kNr / 2;
  if (wide) {
    tile_columns<simd::Double8, kNr>(a, w, kc, C, ldc, rows, cols);
  } else {
    tile_columns<simd::Double4, kHalf>(a, w, kc, C, ldc, rows, std::min(cols, kHalf));
    if (cols > kHalf)
      tile_columns<simd::Double4, kHalf>(a, w + kHalf, kc, C + static_cast<size_t>(kHalf) * ldc, ldc, rows,
                                         cols - kHalf);
  }
}

// Rows [i0, i0 + rows) of X[:, p0 : p0 + kc] (leading dimension ld) into panels of kMr
// rows (zeros past the end): out[(panel * kc + p) * kMr + r].
COROTATE_CLONE_INLINE void pack_rows(const double* X, int ld, int rows, int p0, int kc, int width, double* out) {
  for (int panel = 0; panel * width < rows; ++panel) {
    const int r0 = panel * width, count = std::min(width, rows - r0);
    double* dst = out + static_cast<size_t>(panel) * kc * width;
    for (int p = 0; p < kc; ++p) {
      const double* src = X + static_cast<size_t>(p0 + p) * ld + r0;
      double* d = dst + static_cast<size_t>(p) * width;
      int r = 0;
      for (; r < count; ++r) d[r] = src[r];
      for (; r < width; ++r) d[r] = 0.0;
    }
  }
}

size_t rounded(int rows, int width) { return static_cast<size_t>((rows + width - 1) / width) * width; }

// C (rows x cols) -= A W^T, A rows x depth, W cols x depth (column-major); with `lower`, C is
// square and only its lower triangle is needed (tiles wholly above it are skipped).
COROTATE_CLONE_INLINE void subtract_product(const double* A, int lda, const double* W, int ldw, int rows, int cols,
                                            int depth, double* C, int ldc, bool lower) {
  if (rows <= 0 || cols <= 0 || depth <= 0) return;
  // The 16 x 4 tile's eight accumulators fit in AVX-512's 32 registers as eight-double
  // vectors; with AVX2's 16 the tile runs as two 16 x 2 halves of four-double vectors (A's
  // packed panel, in L1, read twice).
  const bool wide = cpu_runs_avx512_clones();
  for (int p0 = 0; p0 < depth; p0 += kKc) {
    const int kc = std::min(kKc, depth - p0);
    const size_t w_size = rounded(cols, kNr) * kc, a_size = rounded(std::min(rows, kMc), kMr) * kc;
    if (packed_w.size() < w_size) packed_w.resize(w_size);
    if (packed_a.size() < a_size) packed_a.resize(a_size);
    pack_rows(W, ldw, cols, p0, kc, kNr, packed_w.data());
    for (int i0 = 0; i0 < rows; i0 += kMc) {
      const int mc = std::min(kMc, rows - i0);
      pack_rows(A + i0, lda, mc, p0, kc, kMr, packed_a.data());
      const int last_col = lower ? std::min(cols, i0 + mc) : cols;
      for (int j = 0; j < last_col; j += kNr) {
        const int nc = std::min(kNr, cols - j);
        const double* w = packed_w.data() + static_cast<size_t>(j / kNr) * kc * kNr;
        for (int i = 0; i < mc; i += kMr) {
          if (lower && i0 + i + kMr <= j) continue;  // wholly above the diagonal
          tile(packed_a.data() + static_cast<size_t>(i / kMr) * kc * kMr, w, kc,
               C + static_cast<size_t>(j) * ldc + i0 + i, ldc, std::min(kMr, mc - i), nc, wide);
        }
      }
    }
  }
}

// Unblocked: the k x k block at D (leading dimension ld) becomes its Cholesky factor (lower),
// and the `below` rows under it (X, same leading dimension) become X D^-T.
COROTATE_CLONE_INLINE bool factor_block(double* D, int ld, int k, double* X, int below) {
  for (int j = 0; j < k; ++j) {
    double* col = D + static_cast<size_t>(j) * ld;
    const double d = col[j];
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double l = std::sqrt(d), inv = 1.0 / l;
    col[j] = l;
    for (int r = j + 1; r < k; ++r) col[r] *= inv;
    for (int c = j + 1; c < k; ++c) {
      double* target = D + static_cast<size_t>(c) * ld;
      const double f = col[c];
      for (int r = c; r < k; ++r) target[r] -= f * col[r];
    }
  }
  for (int r0 = 0; r0 < below; r0 += kChunkRows) {  // the rows below, a chunk at a time
    const int rows = std::min(kChunkRows, below - r0);
    for (int j = 0; j < k; ++j) {
      double* col = X + static_cast<size_t>(j) * ld + r0;
      const double inv = 1.0 / D[static_cast<size_t>(j) * ld + j];
      for (int r = 0; r < rows; ++r) col[r] *= inv;
      for (int c = j + 1; c < k; ++c) {
        double* target = X + static_cast<size_t>(c) * ld + r0;
        const double f = D[static_cast<size_t>(j) * ld + c];
        for (int r = 0; r < rows; ++r) target[r] -= f * col[r];
      }
    }
  }
  return true;
}

}  // namespace

COROTATE_CPU_CLONES bool factor_panel(double* panel, int m, int k) {
  // Right-looking by blocks of kBlock columns: factor the block and the rows under it, then
  // take its product from the trailing columns (their lower part: rows from the diagonal).
  for (int j0 = 0; j0 < k; j0 += kBlock) {
    const int jb = std::min(kBlock, k - j0), next = j0 + jb;
    double* block = panel + static_cast<size_t>(j0) * m + j0;
    if (!factor_block(block, m, jb, block + jb, m - next)) return false;
    const double* L = panel + static_cast<size_t>(j0) * m + next;  // rows next.., the block's columns
    subtract_product(L, m, L, m, m - next, k - next, jb, panel + static_cast<size_t>(next) * m + next, m, true);
  }
  return true;
}

COROTATE_CPU_CLONES void subtract_lower_product(const double* B, int ldb, int b, int k, double* U) {
  subtract_product(B, ldb, B, ldb, b, b, k, U, b, true);
}

}  // namespace corotate

namespace corotate {

// The small LU (small_dense_lu.hpp) as plain loops over contiguous columns, which the
// compiler vectorises per clone: 26 x 26, 1.9 us against 3.0 us written with Eigen's
// expressions (compiled for the baseline).
COROTATE_CPU_CLONES bool factor_lu(double* a, int n, int* swaps) {
  for (int k = 0; k < n; ++k) {
    double* column_k = a + static_cast<size_t>(k) * n;
    int p = k;
    double pivot = std::abs(column_k[k]);
    for (int i = k + 1; i < n; ++i)
      if (std::abs(column_k[i]) > pivot) pivot = std::abs(column_k[i]), p = i;
    swaps[k] = p;
    if (!(pivot > 0.0) || !std::isfinite(pivot)) return false;
    if (p != k)
      for (int j = 0; j < n; ++j) std::swap(a[static_cast<size_t>(j) * n + k], a[static_cast<size_t>(j) * n + p]);
    const double inverse = 1.0 / column_k[k];
    for (int i = k + 1; i < n; ++i) column_k[i] *= inverse;
    for (int j = k + 1; j < n; ++j) {
      double* column_j = a + static_cast<size_t>(j) * n;
      const double factor = column_j[k];
      for (int i = k + 1; i < n; ++i) column_j[i] -= column_k[i] * factor;
    }
  }
  return true;
}

COROTATE_CPU_CLONES void solve_lu(const double* lu, int n, const int* swaps, double* x) {
  for (int k = 0; k < n; ++k)
    if (swaps[k] != k) std::swap(x[k], x[swaps[k]]);
  for (int k = 0; k < n; ++k) {  // L (unit diagonal), column by column
    const double* column = lu + static_cast<size_t>(k) * n;
    const double xk = x[k];
    for (int i = k + 1; i < n; ++i) x[i] -= column[i] * xk;
  }
  for (int k = n - 1; k >= 0; --k) {  // U
    const double* column = lu + static_cast<size_t>(k) * n;
    x[k] /= column[k];
    const double xk = x[k];
    for (int i = 0; i < k; ++i) x[i] -= column[i] * xk;
  }
}

}  // namespace corotate
