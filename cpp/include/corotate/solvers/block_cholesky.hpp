// A sparse Cholesky factor A = L L^T of a 3x3-block matrix, stored for fast repeated solves.
//
// The nodes are ordered by AMD on the node graph so that each node's three DOFs stay
// together; the factor's block structure comes from the pattern alone (elimination tree,
// row subtrees), and a left-looking sweep over 3x3 blocks computes it in double precision.
// It is kept as 3x3 blocks in single precision (the off-diagonal blocks) with inverted
// diagonal blocks in double. A solve reads 9 floats and one index per block instead of 9
// doubles and 9 indices: on large factors the triangular solves are memory bound, so this is
// what makes a reused factorization cheap enough to precondition every step. Single
// precision is ample for a preconditioner: CG still converges to the tolerance it is given.
// Small factors, which fit in cache, are bound by the latency of dependent operations instead
// of bytes: they are arranged for it (arrange_for_latency: columns level by level of the
// elimination tree, the blocks kept by rows too so that both sweeps of solve_single sum in
// registers).
#pragma once

#include <cstddef>
#include <vector>

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class BlockCholesky {
 public:
  // Factors of up to this many bytes of off-diagonal blocks are arranged for latency.
  static constexpr size_t kLatencyBoundBytes = 256 * 1024;
  // Factorizes A (symmetric positive definite); throws NotPositiveDefinite otherwise (and is
  // then empty). latency_bound_bytes: the largest factor arranged for latency (a test sets it
  // to reach both arrangements). A matrix of the same pattern as the last one factorized
  // keeps the ordering and the factor's structure, which depend on the pattern alone, and
  // computes the blocks only (refactorize_numerically), in about half the time (timings:
  // docs/notes/performance.md). A preconditioner that refreshes its factor as contacts come
  // and go pays that each time.
  void factorize(const BlockSparseMatrix& A, size_t latency_bound_bytes = kLatencyBoundBytes);
  bool empty() const { return order_.empty(); }
  // x = A^-1 b (approximately: single-precision factor). x and b: num_dofs. With `turn`
  // (one rotation per node), x = R A^-1 R^T b instead, R = diag(turn[i]) (the reference
  // factor turned with the body), applied as the right-hand side is read in and the solution
  // written out.
  void solve(const Vec& b, Vec& x, const Mat3* turn = nullptr);
  // The same with the sums in float32 too (the work vector four floats per node: every block
  // is three four-wide multiply-adds, where the double sums convert each of its nine
  // values): for a preconditioner of CG at a loose tolerance, which multiplies in float32
  // anyway (relative 1e-7 of a solve that aims at 1e-2).
  void solve_single(const Vec& b, Vec& x, const Mat3* turn = nullptr);
  Index factor_blocks() const { return static_cast<Index>(rows_.size()); }
  // What a numeric refactorization costs in solves, from the structure: column k's c_k
  // off-diagonal blocks take c_k (c_k + 1) / 2 block products (27 multiply-adds each) to
  // factorize, and a solve reads each block twice (9 each). For a preconditioner deciding
  // whether a fresh factor pays. (Of the structure: computed when it is.)
  double refactorization_cost_in_solves() const { return refactorization_cost_; }
  // The elimination order: order()[k] is the node eliminated k-th.
  const std::vector<int>& order() const { return order_; }
  // Whether it was arranged for latency (a small factor).
  bool arranged_for_latency() const { return arranged_; }
  // Factorizations that kept the last one's ordering and structure.
  int numeric_refactorizations() const { return numeric_refactorizations_; }

 private:
  void arrange_for_latency();
  // The off-diagonal blocks indexed by rows (row_start_, row_columns_, row_block_).
  void index_by_rows();
  bool same_pattern(const BlockSparseMatrix& A, size_t latency_bound_bytes) const;
  double structure_cost_in_solves() const;  // refactorization_cost_in_solves, from column_start_
  double refactorization_cost_ = 0;
  // A's blocks into the kept structure: a left-looking block Cholesky in double precision.
  void refactorize_numerically(const BlockSparseMatrix& A);
  // Packs the float32 copies (blocks_ from factor_, row_blocks_, inverse_diagonal_single_).
  void pack_single();
  std::vector<int> order_;             // order_[k] = node placed at position k
  std::vector<int> column_start_;      // block column k: off-diagonal blocks [start[k], start[k+1])
  std::vector<int> rows_;              // block row (position) of each off-diagonal block
  // 9 per off-diagonal block, column by column (entry (r, c) at 3 c + r), then 3 zeros: a
  // column read four wide takes the next value along (solve_single keeps it out of its sums).
  std::vector<float> blocks_;
  // The off-diagonal blocks by rows: row k's are row_block_[row_start_[k] ...
  // row_start_[k + 1]) (indices into the columns' list), in block columns row_columns_.
  std::vector<int> row_start_, row_columns_, row_block_;
  // For a factor arranged for latency, those blocks' values in that order for solve_single's
  // forward sweep, each stored by rows (entry (r, c) at 3 r + c), then 3 zeros; else empty.
  std::vector<float> row_blocks_;
  bool arranged_ = false;
  // What a numeric refactorization needs: the pattern factorized (A's row starts and
  // columns), each node's position, the factor in double precision and a work column.
  std::vector<int> pattern_start_, pattern_columns_, position_;
  size_t latency_bound_bytes_ = 0;
  std::vector<Mat3> factor_;  // the off-diagonal blocks L_ik, as blocks_
  std::vector<Mat3> column_work_;
  int numeric_refactorizations_ = 0;
  std::vector<Mat3> inverse_diagonal_; // L_kk^-1 (lower triangular)
  // Per node, the columns of L_kk^-1 and then of L_kk^-T, four floats each (the fourth 0).
  std::vector<float> inverse_diagonal_single_;
  Vec work_;
  std::vector<float> work_single_;  // four per node
};

}  // namespace corotate
