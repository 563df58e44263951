#include "corotate/solvers/lu_solver.hpp"

namespace corotate {

SolveStats LuSolver::solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) {
  A.copy_to(rows_);
  scalar_ = rows_.transpose();
  if (!analysed_) {
    lu_.analyzePattern(scalar_);
    analysed_ = true;
  }
  lu_.factorize(scalar_);
  if (lu_.info() != Eigen::Success) throw SolverFailure("LU solver: the system matrix is singular");
  x = lu_.solve(b);
  return {0, relative_residual(A, b, x, residual_), true};
}

}  // namespace corotate
