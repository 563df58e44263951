#include "corotate/solvers/block_cholesky.hpp"

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <cstring>

#include "corotate/cpu_clones.hpp"
#include "corotate/sparse/symmetric_product.hpp"  // Four, load4, sum3

namespace corotate {

namespace {

// Node `node`'s entries of b, turned back by the node's rotation when turning.
COROTATE_CLONE_INLINE Vec3 read_in(const Vec& b, int node, const Mat3* turn) {
  const Vec3 v = b.segment<3>(3 * node);
  return turn ? Vec3(turn[node].transpose() * v) : v;
}

COROTATE_CLONE_INLINE void write_out(Vec& x, int node, const Vec3& v, const Mat3* turn) {
  x.segment<3>(3 * node) = turn ? Vec3(turn[node] * v) : v;
}

}  // namespace

void BlockCholesky::factorize(const BlockSparseMatrix& A, size_t latency_bound_bytes) {
  if (same_pattern(A, latency_bound_bytes)) {
    refactorize_numerically(A);
    ++numeric_refactorizations_;
    return;
  }
  const Index n = A.num_nodes();
  const auto& start = A.row_start();
  const auto& cols = A.columns();
  order_.clear();  // (empty until it succeeds)

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
  std::vector<int> order(inverse_permutation.indices().data(), inverse_permutation.indices().data() + n);
  std::vector<int> position(n);
  for (Index k = 0; k < n; ++k) position[order[k]] = static_cast<int>(k);

  // 2. The factor's structure from the pattern alone (the block version of a symbolic
  // Cholesky): the elimination tree by Liu's algorithm, then each row k of L as the nodes
  // met walking up the tree from every A(k, j), j < k, to k. Rows come in ascending order, so
  // each column's list is sorted.
  std::vector<int> parent(n, -1), ancestor(n, -1), mark(n, -1), count(n, 0);
  const auto lower_neighbours = [&](Index k, auto&& visit) {
    const int node = order[k];
    for (int e = start[node]; e < start[node + 1]; ++e)
      if (position[cols[e]] < k) visit(position[cols[e]]);
  };
  for (Index k = 0; k < n; ++k)
    lower_neighbours(k, [&](int j) {
      int r = j;
      while (ancestor[r] != -1 && ancestor[r] != k) {
        const int next = ancestor[r];
        ancestor[r] = static_cast<int>(k);
        r = next;
      }
      if (ancestor[r] == -1) ancestor[r] = parent[r] = static_cast<int>(k);
    });
  const auto row_of_L = [&](Index k, auto&& visit) {  // the columns r < k with L(k, r) != 0
    mark[k] = static_cast<int>(k);
    lower_neighbours(k, [&](int j) {
      for (int r = j; mark[r] != k; r = parent[r]) {
        mark[r] = static_cast<int>(k);
        visit(r);
      }
    });
  };
  for (Index k = 0; k < n; ++k) row_of_L(k, [&](int r) { ++count[r]; });
  column_start_.assign(n + 1, 0);
  for (Index k = 0; k < n; ++k) column_start_[k + 1] = column_start_[k] + count[k];
  rows_.assign(column_start_[n], 0);
  std::fill(mark.begin(), mark.end(), -1);
  std::vector<int> next(column_start_.begin(), column_start_.end() - 1);
  for (Index k = 0; k < n; ++k) row_of_L(k, [&](int r) { rows_[next[r]++] = static_cast<int>(k); });
  order_.swap(order);

  // A factor that fits in a core's cache is arranged for latency (a larger one would then
  // no longer fit, or lose the locality of AMD's postorder).
  arranged_ = 9 * rows_.size() * sizeof(float) <= latency_bound_bytes;
  if (arranged_) arrange_for_latency();
  index_by_rows();
  refactorization_cost_ = structure_cost_in_solves();
  position_.resize(n);
  for (Index k = 0; k < n; ++k) position_[order_[k]] = static_cast<int>(k);
  work_.resize(3 * n);
  work_single_.assign(4 * n, 0.0f);
  // 3. The numbers (the same left-looking sweep a refactorization runs; empty on failure).
  refactorize_numerically(A);
  pattern_start_ = start;
  pattern_columns_ = cols;
  latency_bound_bytes_ = latency_bound_bytes;
}

bool BlockCholesky::same_pattern(const BlockSparseMatrix& A, size_t latency_bound_bytes) const {
  return !order_.empty() && latency_bound_bytes == latency_bound_bytes_ && A.row_start() == pattern_start_ &&
         A.columns() == pattern_columns_;
}

void BlockCholesky::refactorize_numerically(const BlockSparseMatrix& A) {
  // Left-looking, column by column in elimination order: column k of L is A's column k less
  // the products L_ij L_kj^T of every earlier column j that has a block in row k, the blocks
  // below the diagonal then multiplied by L_kk^-T. The structure (which L_ik exist) is the
  // kept one: it holds every block these updates reach.
  const Index n = static_cast<Index>(order_.size());
  const auto& start = A.row_start();
  const auto& cols = A.columns();
  factor_.resize(rows_.size());  // (every block and diagonal is written below)
  inverse_diagonal_.resize(n);
  column_work_.resize(n);
  for (Index k = 0; k < n; ++k) {
    for (int p = column_start_[k]; p < column_start_[k + 1]; ++p) column_work_[rows_[p]].setZero();
    Mat3 diagonal = Mat3::Zero();
    const int node = order_[k];
    for (int e = start[node]; e < start[node + 1]; ++e) {
      const int i = position_[cols[e]];
      if (i == k) diagonal = A.block(e);
      else if (i > k) column_work_[i] = A.block(e).transpose();  // A(i, k) = A(k, i)^T
    }
    for (int q = row_start_[k]; q < row_start_[k + 1]; ++q) {
      const int j = row_columns_[q];
      const Mat3 Lkj = factor_[row_block_[q]];
      diagonal.noalias() -= Lkj * Lkj.transpose();
      for (int p = column_start_[j]; p < column_start_[j + 1]; ++p)
        if (rows_[p] > k) column_work_[rows_[p]].noalias() -= factor_[p] * Lkj.transpose();
    }
    const Eigen::LLT<Mat3> llt(diagonal);
    if (llt.info() != Eigen::Success || !diagonal.allFinite()) {
      order_.clear();  // empty: the next factorization starts afresh
      throw NotPositiveDefinite("Cholesky factorization failed: the matrix is not positive definite");
    }
    const Mat3 inverse = Mat3(llt.matrixL()).triangularView<Eigen::Lower>().solve(Mat3::Identity());
    inverse_diagonal_[k] = inverse;
    for (int p = column_start_[k]; p < column_start_[k + 1]; ++p)
      factor_[p].noalias() = column_work_[rows_[p]] * inverse.transpose();
  }
  pack_single();
}

void BlockCholesky::pack_single() {
  const size_t blocks = rows_.size();
  blocks_.assign(9 * blocks + 3, 0.0f);
  for (size_t p = 0; p < blocks; ++p)
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) blocks_[9 * p + 3 * c + r] = static_cast<float>(factor_[p](r, c));
  if (arranged_) {
    row_blocks_.assign(9 * blocks + 3, 0.0f);
    for (size_t q = 0; q < blocks; ++q)  // stored by rows: a row reads four wide like a column
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) row_blocks_[9 * q + 3 * r + c] = static_cast<float>(factor_[row_block_[q]](r, c));
  } else {
    row_blocks_.clear();
  }
  const size_t n = order_.size();
  inverse_diagonal_single_.assign(24 * n, 0.0f);
  for (size_t k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) {
        inverse_diagonal_single_[24 * k + 4 * c + r] = static_cast<float>(inverse_diagonal_[k](r, c));
        inverse_diagonal_single_[24 * k + 12 + 4 * c + r] = static_cast<float>(inverse_diagonal_[k](c, r));
      }
  // A large factor keeps only its float32 copy: the double one is rebuilt by a refactorization.
  if (!arranged_) std::vector<Mat3>().swap(factor_);
}

void BlockCholesky::index_by_rows() {
  const Index n = static_cast<Index>(order_.size());
  row_start_.assign(n + 1, 0);
  for (int row : rows_) ++row_start_[row + 1];
  for (Index k = 0; k < n; ++k) row_start_[k + 1] += row_start_[k];
  row_columns_.resize(rows_.size());
  row_block_.resize(rows_.size());
  std::vector<int> next(row_start_.begin(), row_start_.end() - 1);
  for (Index k = 0; k < n; ++k)  // columns ascending: each row's blocks come in column order
    for (int p = column_start_[k]; p < column_start_[k + 1]; ++p) {
      const int q = next[rows_[p]]++;
      row_columns_[q] = static_cast<int>(k);
      row_block_[q] = p;
    }
}

void BlockCholesky::arrange_for_latency() {
  const Index n = static_cast<Index>(order_.size());
  // The positions level by level of the elimination tree: first every leaf, then every
  // node whose children are all leaves, and so on (AMD's order within a level). A node's
  // parent is the first block row below its diagonal, on a higher level, so the new order is
  // another order of the same tree: the same factor, its columns stored elsewhere. In AMD's
  // postorder a column is mostly followed by its parent, which waits for it (a chain of
  // dependent loads, stores and multiply-adds that the processor cannot overlap); within a
  // level no column waits for another. Only the tree's top (a node per level) stays a chain.
  // (solve_single's forward sweep then reads the blocks by rows: index_by_rows, pack_single.)
  std::vector<int> level(n, 0);
  for (Index k = 0; k < n; ++k) {
    if (column_start_[k] == column_start_[k + 1]) continue;  // a root
    const int parent = *std::min_element(rows_.begin() + column_start_[k], rows_.begin() + column_start_[k + 1]);
    level[parent] = std::max(level[parent], level[k] + 1);
  }
  std::vector<int> by_level(n), position(n);
  for (Index k = 0; k < n; ++k) by_level[k] = static_cast<int>(k);
  std::stable_sort(by_level.begin(), by_level.end(), [&](int a, int b) { return level[a] < level[b]; });
  for (Index k = 0; k < n; ++k) position[by_level[k]] = static_cast<int>(k);
  // (Only the structure moves: the numbers are computed afterwards, in the new order.)
  std::vector<int> order(n), column_start(1, 0), rows;
  rows.reserve(rows_.size());
  for (Index m = 0; m < n; ++m) {
    const int k = by_level[m];
    order[m] = order_[k];
    for (int p = column_start_[k]; p < column_start_[k + 1]; ++p) rows.push_back(position[rows_[p]]);
    column_start.push_back(static_cast<int>(rows.size()));
  }
  order_.swap(order), column_start_.swap(column_start), rows_.swap(rows);
}

void BlockCholesky::solve(const Vec& b, Vec& x, const Mat3* turn) {
  const Index n = static_cast<Index>(order_.size());
  double* w = work_.data();
  for (Index k = 0; k < n; ++k) Eigen::Map<Vec3>(w + 3 * k) = read_in(b, order_[k], turn);

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
  for (Index k = 0; k < n; ++k) write_out(x, order_[k], Eigen::Map<const Vec3>(w + 3 * k), turn);
}

double BlockCholesky::structure_cost_in_solves() const {
  double products = 0, blocks = 0;
  for (size_t k = 0; k + 1 < column_start_.size(); ++k) {
    const double c = column_start_[k + 1] - column_start_[k];
    products += 0.5 * c * (c + 1);
    blocks += c;
  }
  return blocks > 0 ? (27 * products) / (18 * blocks) : 0.0;
}

COROTATE_CPU_CLONES void BlockCholesky::solve_single(const Vec& b, Vec& x, const Mat3* turn) {
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
    const Vec3 bk = read_in(b, order_[k], turn);
    store4(w + 4 * k, V{float(bk[0]), float(bk[1]), float(bk[2]), 0.0f});
  }
  // A pulling sweep: a node's new value is its own right-hand side minus the products of
  // 3x3 blocks with values already solved, summed in registers (two sets of sums, even and
  // odd blocks, so that a block's multiply-adds do not wait for the last block's) and
  // stored once. Each block row times x_i is taken lane-wise and summed across three lanes
  // once; a row read four wide takes the next value along into the fourth lane, which meets
  // x_i's fourth lane, 0.
  const auto dot_blocks = [w](const float* values, const int* index, int p, int end, float out[3]) {
    V a0 = {0, 0, 0, 0}, a1 = a0, a2 = a0, c0 = a0, c1 = a0, c2 = a0;
    const auto add_block = [&](int q, V& s0, V& s1, V& s2) {
      const float* L = values + 9 * q;
      const V xi = load4(w + 4 * index[q]);
      s0 += load4(L) * xi;
      s1 += load4(L + 3) * xi;
      s2 += load4(L + 6) * xi;
    };
    for (; p + 1 < end; p += 2) {
      add_block(p, a0, a1, a2);
      add_block(p + 1, c0, c1, c2);
    }
    if (p < end) add_block(p, a0, a1, a2);
    out[0] = sum3(a0 + c0), out[1] = sum3(a1 + c1), out[2] = sum3(a2 + c2);
  };
  if (arranged_) {
    // Forward: L y = b pulling, y_k = L_kk^-1 (b_k - sum_j<k L_kj y_j) over row k's blocks.
    // Pushing each solved y_k into the entries that still wait for it (the column sweep
    // below) is a load, subtract and store of the same entry by block after block, each
    // waiting for the store before: on a factor in cache that chain, not the bytes, is
    // what a sweep waits for.
    const float* row_blocks = row_blocks_.data();
    const int* row_columns = row_columns_.data();
    const int* row_start = row_start_.data();
    for (Index k = 0; k < n; ++k) {
      float s[3];
      dot_blocks(row_blocks, row_columns, row_start[k], row_start[k + 1], s);
      const float* wk = w + 4 * k;
      const float t0 = wk[0] - s[0], t1 = wk[1] - s[1], t2 = wk[2] - s[2];
      const float* d = diagonal + 24 * k;
      store4(w + 4 * k, t0 * load4(d) + t1 * load4(d + 4) + t2 * load4(d + 8));
    }
  } else {
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
  }
  // Backward: L^T x = y; x_k = L_kk^-T (y_k - sum_i>k L_ik^T x_i) over column k's blocks
  // (column c of L_ik dotted with x_i).
  for (Index k = n - 1; k >= 0; --k) {
    float s[3];
    dot_blocks(blocks, rows, column_start[k], column_start[k + 1], s);
    const float* wk = w + 4 * k;
    const float t0 = wk[0] - s[0], t1 = wk[1] - s[1], t2 = wk[2] - s[2];
    const float* d = diagonal + 24 * k + 12;
    store4(w + 4 * k, t0 * load4(d) + t1 * load4(d + 4) + t2 * load4(d + 8));
  }
  for (Index k = 0; k < n; ++k) write_out(x, order_[k], Vec3(w[4 * k], w[4 * k + 1], w[4 * k + 2]), turn);
}

}  // namespace corotate
