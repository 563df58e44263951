#include "corotate/solvers/direct_solver.hpp"

namespace corotate {

SolveStats DirectSolver::solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) {
  A.copy_to(scalar_);
  if (!analysed_) {
    ldlt_.analyzePattern(scalar_);
    analysed_ = true;
  }
  ldlt_.factorize(scalar_);
  if (ldlt_.info() != Eigen::Success || (ldlt_.vectorD().array() <= 0).any())
    throw NotPositiveDefinite(
        "direct solver: the system matrix is not positive definite "
        "(an unconstrained body under a static load, or a non-physical material?)");
  x = ldlt_.solve(b);
  return {0, relative_residual(A, b, x, residual_), true};
}

}  // namespace corotate
