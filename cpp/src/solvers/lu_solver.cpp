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
  residual_.resize(b.size());
  A.multiply(x, residual_);
  residual_ -= b;
  const double bn = b.norm();
  return {0, bn > 0 ? residual_.norm() / bn : residual_.norm(), true};
}

}  // namespace corotate
