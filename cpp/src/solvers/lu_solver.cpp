#include "corotate/solvers/lu_solver.hpp"

#include "corotate/solvers/coupled_matrix.hpp"

namespace corotate {

SolveStats LuSolver::solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) {
  if (coupling_) {
    const BlockSparseMatrix coupled = with_coupling(A, *coupling_);
    ScalarMatrix rows;
    coupled.copy_to(rows);
    const ScalarMatrix scalar = rows.transpose();
    coupled_lu_.analyzePattern(scalar);
    coupled_lu_.factorize(scalar);
    if (coupled_lu_.info() != Eigen::Success) throw SolverFailure("LU solver: the system matrix is singular");
    x = coupled_lu_.solve(b);
    return {0, relative_residual(coupled, b, x, residual_), true};
  }
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
