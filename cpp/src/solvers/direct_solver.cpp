#include "corotate/solvers/direct_solver.hpp"

namespace corotate {

SolveStats DirectSolver::solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) {
  A.copy_to(scalar_);
  if (!analysed_) {
    cholesky_.analyze(scalar_);
    analysed_ = true;
  }
  if (!cholesky_.factorize(scalar_))
    throw NotPositiveDefinite(
        "direct solver: the system matrix is not positive definite "
        "(an unconstrained body under a static load, or a non-physical material?)");
  cholesky_.solve(b, x);
  return {0, relative_residual(A, b, x, residual_), true};
}

}  // namespace corotate
