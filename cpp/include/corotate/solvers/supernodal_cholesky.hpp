// The library's own supernodal sparse Cholesky factorization P A P^T = L L^T, so that a build
// without SuiteSparse (a plain `pip install .`, the prebuilt wheel) has no direct-solver cliff:
// Eigen's SimplicialLDLT works one column at a time and took 84-88 s per step at 122,880 tets.
//
// Analysis (supernodal_symbolic.cpp), once per pattern: AMD ordering (Eigen's), elimination
// tree, postorder, column counts from row subtrees, fundamental supernodes relaxed by
// amalgamation (small supernodes merged with their parent where few explicit zeros come in:
// dense kernels on wider panels pay more than the zeros cost), and each supernode's rows.
// Factorization (supernodal_numeric.cpp): multifrontal, in postorder. Each supernode's front
// gathers its columns of A and its children's update matrices (extend-add); the dense part is
// a Cholesky of the diagonal block, a triangular solve for the rows below and the update
// matrix U = F22 - L21 L21^T passed up to the parent (dense_kernels.hpp, compiled per CPU).
// The factor is kept in CHOLMOD's supernodal layout, so supernodal_solve does its solves.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

#include "corotate/common.hpp"
#include "corotate/solvers/supernodal_solve.hpp"

namespace corotate {

class SupernodalCholesky {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  // Symbolic analysis of A's pattern (full symmetric storage, compressed).
  void analyze(const Matrix& A);
  // Numeric factorization of A (the analysed pattern); false when A is not positive definite.
  bool factorize(const Matrix& A);
  // The factor's arrays (valid after a successful factorize) and values.
  const SupernodalFactor& factor() const { return view_; }
  const double* values() const { return values_.data(); }
  // Entries of L, with the explicit zeros of relaxed supernodes.
  size_t num_values() const { return values_.size(); }

 private:
  // The symbolic factor.
  std::vector<int> perm_, inverse_perm_, super_, pi_, px_, rows_, first_child_, next_sibling_;
  // Per supernode: where its children's update matrices start on the stack (in doubles) and
  // where its own is computed (right above them).
  std::vector<size_t> children_start_, update_start_;
  SupernodalFactor view_;
  // Numeric work, sized by analyze.
  std::vector<double> values_, stack_;
  std::vector<int> relative_, map_;
  Index analysed_nonzeros_ = -1;
};

}  // namespace corotate
