#include "corotate/solvers/direct_solver.hpp"

#include "corotate/solvers/coupled_matrix.hpp"

namespace corotate {

SolveStats DirectSolver::solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) {
  // (The hint holds for one solve, and only for the matrix factorized last: another one, a
  // static solve's tangent say, is factorized.)
  const bool same = same_matrix_next_ && factorized_ == &A;
  same_matrix_next_ = false;
  if (coupling_) return solve_coupled(A, b, x);
  if (same) {
    ++factor_reuses_;
  } else {
    factorized_ = nullptr;
    A.copy_to(scalar_);
    if (!analysed_) {
      cholesky_.analyze(scalar_);
      analysed_ = true;
    }
    if (!cholesky_.factorize(scalar_)) throw not_positive_definite();
    factorized_ = &A;
  }
  cholesky_.solve(b, x);
  return {0, relative_residual(A, b, x, residual_), true};
}

NotPositiveDefinite DirectSolver::not_positive_definite() {
  return NotPositiveDefinite(
      "direct solver: the system matrix is not positive definite "
      "(an unconstrained body under a static load, or a non-physical material?)");
}

// (A + C) x = b with A + C factorized whole (coupled_matrix.hpp): its pattern follows the
// contacts, so it is analysed afresh (apart from A's own analysis, kept for the solves
// without coupling).
SolveStats DirectSolver::solve_coupled(const BlockSparseMatrix& A, const Vec& b, Vec& x) {
  const BlockSparseMatrix coupled = with_coupling(A, *coupling_);
  SparseCholesky::Matrix scalar;
  coupled.copy_to(scalar);
  coupled_cholesky_.analyze(scalar);
  if (!coupled_cholesky_.factorize(scalar)) throw not_positive_definite();
  coupled_cholesky_.solve(b, x);
  return {0, relative_residual(coupled, b, x, residual_), true};
}

}  // namespace corotate
