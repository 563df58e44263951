#include "corotate/solvers/block_cholesky.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cstring>

#include "corotate/cpu_clones.hpp"
#include "corotate/sparse/symmetric_product.hpp"  // Four, load4, sum3

namespace corotate {

void BlockCholesky::factorize(const BlockSparseMatrix& A) {
  const Index n = A.num_nodes();
  const auto& start = A.row_start();
  const auto& cols = A.columns();

  // 1. AMD ordering of the node graph.
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> graph(n, n);
  {
    std::vector<Eigen::Triplet<double, int>> t;
    t.reserve(cols.size());
    for (Index i = 0; i < n; ++i)
      for (int k = start[i]; k < start[i + 1]; ++k) t.emplace_back(static_cast<int>(i), cols[k], 1.0);
    graph.setFromTriplets(t.begin(), t.end());
  }
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse_permutation;
  Eigen::AMDOrdering<int>()(graph, inverse_permutation);
  order_.assign(inverse_permutation.indices().data(), inverse_permutation.indices().data() + n);
  std::vector<int> position(n);
  for (Index k = 0; k < n; ++k) position[order_[k]] = static_cast<int>(k);

  // 2. The permuted scalar matrix, factorized in natural order.
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> permuted(3 * n, 3 * n);
  {
    std::vector<Eigen::Triplet<double, int>> t;
    t.reserve(9 * cols.size());
    for (Index i = 0; i < n; ++i)
      for (int k = start[i]; k < start[i + 1]; ++k) {
        const auto block = A.block(k);
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) t.emplace_back(3 * position[i] + r, 3 * position[cols[k]] + c, block(r, c));
      }
    permuted.setFromTriplets(t.begin(), t.end());
  }
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double, Eigen::ColMajor, int>, Eigen::Lower, Eigen::NaturalOrdering<int>>
      llt(permuted);
  if (llt.info() != Eigen::Success) {
    order_.clear();
    throw NotPositiveDefinite("Cholesky factorization failed: the matrix is not positive definite");
  }
  const auto& L = llt.matrixL().nestedExpression();  // CSC, lower triangular

  // 3. Repack as 3x3 blocks. Column k's three scalar columns share their block rows.
  column_start_.assign(1, 0);
  rows_.clear();
  blocks_.clear();
  inverse_diagonal_.assign(n, Mat3::Zero());
  std::vector<int> slot(n, -1);  // block row -> index in this column's list
  for (Index k = 0; k < n; ++k) {
    const int first = static_cast<int>(rows_.size());
    Mat3 diagonal = Mat3::Zero();
    for (int c = 0; c < 3; ++c)
      for (Eigen::SparseMatrix<double, Eigen::ColMajor, int>::InnerIterator it(L, 3 * k + c); it; ++it) {
        const int row_block = it.row() / 3, r = it.row() % 3;
        if (row_block == k) {
          diagonal(r, c) = it.value();
          continue;
        }
        if (slot[row_block] < 0) {
          slot[row_block] = static_cast<int>(rows_.size());
          rows_.push_back(row_block);
          blocks_.resize(blocks_.size() + 9, 0.0f);
        }
        blocks_[9 * slot[row_block] + 3 * c + r] = static_cast<float>(it.value());
      }
    for (size_t b = first; b < rows_.size(); ++b) slot[rows_[b]] = -1;
    column_start_.push_back(static_cast<int>(rows_.size()));
    inverse_diagonal_[k] = diagonal.triangularView<Eigen::Lower>().solve(Mat3::Identity());
  }
  blocks_.resize(blocks_.size() + 3, 0.0f);
  inverse_diagonal_single_.assign(24 * n, 0.0f);
  for (Index k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) {
        inverse_diagonal_single_[24 * k + 4 * c + r] = static_cast<float>(inverse_diagonal_[k](r, c));
        inverse_diagonal_single_[24 * k + 12 + 4 * c + r] = static_cast<float>(inverse_diagonal_[k](c, r));
      }
  work_.resize(3 * n);
  work_single_.assign(4 * n, 0.0f);
}

void BlockCholesky::solve(const Vec& b, Vec& x) {
  const Index n = static_cast<Index>(order_.size());
  double* w = work_.data();
  for (Index k = 0; k < n; ++k)
    for (int r = 0; r < 3; ++r) w[3 * k + r] = b[3 * order_[k] + r];

  // Forward: L y = b, column by column.
  for (Index k = 0; k < n; ++k) {
    const Vec3 y = inverse_diagonal_[k] * Eigen::Map<const Vec3>(w + 3 * k);
    Eigen::Map<Vec3>(w + 3 * k) = y;
    for (int p = column_start_[k]; p < column_start_[k + 1]; ++p) {
      const float* L = blocks_.data() + 9 * p;
      double* wi = w + 3 * rows_[p];
      wi[0] -= L[0] * y[0] + L[3] * y[1] + L[6] * y[2];
      wi[1] -= L[1] * y[0] + L[4] * y[1] + L[7] * y[2];
      wi[2] -= L[2] * y[0] + L[5] * y[1] + L[8] * y[2];
    }
  }
  // Backward: L^T x = y, row of L^T = column of L.
  for (Index k = n - 1; k >= 0; --k) {
    double t0 = w[3 * k], t1 = w[3 * k + 1], t2 = w[3 * k + 2];
    for (int p = column_start_[k]; p < column_start_[k + 1]; ++p) {
      const float* L = blocks_.data() + 9 * p;
      const double* xi = w + 3 * rows_[p];
      t0 -= L[0] * xi[0] + L[1] * xi[1] + L[2] * xi[2];
      t1 -= L[3] * xi[0] + L[4] * xi[1] + L[5] * xi[2];
      t2 -= L[6] * xi[0] + L[7] * xi[1] + L[8] * xi[2];
    }
    Eigen::Map<Vec3>(w + 3 * k) = inverse_diagonal_[k].transpose() * Vec3(t0, t1, t2);
  }
  for (Index k = 0; k < n; ++k)
    for (int r = 0; r < 3; ++r) x[3 * order_[k] + r] = w[3 * k + r];
}

COROTATE_CPU_CLONES void BlockCholesky::solve_single(const Vec& b, Vec& x) {
  using V = Four<float>::type;
  const auto store4 = [](float* p, V v) { std::memcpy(p, &v, sizeof v); };
  const Index n = static_cast<Index>(order_.size());
  float* w = work_single_.data();
  const float* blocks = blocks_.data();
  const float* diagonal = inverse_diagonal_single_.data();
  // The index arrays as locals: store4's memcpy may alias anything, so the members' data
  // pointers (and each column's end) would be loaded again after every block's store.
  const int* rows = rows_.data();
  const int* column_start = column_start_.data();
  for (Index k = 0; k < n; ++k) {
    const double* bk = b.data() + 3 * order_[k];
    store4(w + 4 * k, V{float(bk[0]), float(bk[1]), float(bk[2]), 0.0f});
  }
  // Forward: L y = b, column by column; y_k = L_kk^-1 w_k, then w_i -= L_ik y_k, each block
  // as its three columns times y_k's entries. A column's fourth lane (the next value in
  // memory) only ever lands in w_i's fourth, which no sum reads, and y_k's fourth is 0.
  for (Index k = 0; k < n; ++k) {
    const V wk = load4(w + 4 * k);
    const float* d = diagonal + 24 * k;
    const V y = wk[0] * load4(d) + wk[1] * load4(d + 4) + wk[2] * load4(d + 8);
    store4(w + 4 * k, y);
    const float y0 = y[0], y1 = y[1], y2 = y[2];  // a scalar times a vector: a broadcast
    for (int p = column_start[k], end = column_start[k + 1]; p < end; ++p) {
      const float* L = blocks + 9 * p;
      float* wi = w + 4 * rows[p];
      store4(wi, load4(wi) - (load4(L) * y0 + load4(L + 3) * y1 + load4(L + 6) * y2));
    }
  }
  // Backward: L^T x = y; (L_ik^T x_i)_c = column c . x_i, summed lane-wise over the column's
  // blocks and across the three lanes once (x_i's fourth lane is 0).
  // Two sets of sums, even and odd blocks: with one, each block's three multiply-adds wait
  // for the last block's (four cycles of latency), about twice what its loads and
  // multiply-adds take.
  for (Index k = n - 1; k >= 0; --k) {
    V a0 = {0, 0, 0, 0}, a1 = a0, a2 = a0, c0 = a0, c1 = a0, c2 = a0;
    const auto add_block = [&](int p, V& s0, V& s1, V& s2) {
      const float* L = blocks + 9 * p;
      const V xi = load4(w + 4 * rows[p]);
      s0 += load4(L) * xi;
      s1 += load4(L + 3) * xi;
      s2 += load4(L + 6) * xi;
    };
    int p = column_start[k];
    const int end = column_start[k + 1];
    for (; p + 1 < end; p += 2) {
      add_block(p, a0, a1, a2);
      add_block(p + 1, c0, c1, c2);
    }
    if (p < end) add_block(p, a0, a1, a2);
    a0 += c0, a1 += c1, a2 += c2;
    const float* wk = w + 4 * k;
    const float t0 = wk[0] - sum3(a0), t1 = wk[1] - sum3(a1), t2 = wk[2] - sum3(a2);
    const float* d = diagonal + 24 * k + 12;
    store4(w + 4 * k, t0 * load4(d) + t1 * load4(d + 4) + t2 * load4(d + 8));
  }
  for (Index k = 0; k < n; ++k)
    for (int r = 0; r < 3; ++r) x[3 * order_[k] + r] = w[4 * k + r];
}

}  // namespace corotate
