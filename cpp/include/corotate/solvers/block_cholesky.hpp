// A sparse Cholesky factor A = L L^T of a 3x3-block matrix, stored for fast repeated solves.
//
// The nodes are ordered by AMD on the node graph so that each node's three DOFs stay
// together; Eigen's SimplicialLLT factorizes the permuted matrix, and the factor is then
// repacked as 3x3 blocks in single precision (the off-diagonal blocks) with inverted
// diagonal blocks in double. A solve reads 9 floats and one index per block instead of
// 9 doubles and 9 indices: the triangular solves are memory bound, so this is what makes a
// reused factorization cheap enough to precondition every step. Single precision is ample
// for a preconditioner: CG still converges to the tolerance it is given.
#pragma once

#include <vector>

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class BlockCholesky {
 public:
  // Factorizes A (symmetric positive definite); throws SolverFailure otherwise.
  void factorize(const BlockSparseMatrix& A);
  bool empty() const { return order_.empty(); }
  // x = A^-1 b (approximately: single-precision factor). x and b: num_dofs.
  void solve(const Vec& b, Vec& x);
  Index factor_blocks() const { return static_cast<Index>(rows_.size()); }

 private:
  std::vector<int> order_;             // order_[k] = node placed at position k
  std::vector<int> column_start_;      // block column k: off-diagonal blocks [start[k], start[k+1])
  std::vector<int> rows_;              // block row (position) of each off-diagonal block
  std::vector<float> blocks_;          // 9 per off-diagonal block, row-major
  std::vector<Mat3> inverse_diagonal_; // L_kk^-1 (lower triangular)
  Vec work_;
};

}  // namespace corotate
