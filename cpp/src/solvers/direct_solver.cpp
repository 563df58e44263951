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
  residual_.resize(b.size());
  A.multiply(x, residual_);
  residual_ -= b;
  const double bn = b.norm();
  return {0, bn > 0 ? residual_.norm() / bn : residual_.norm(), true};
}

}  // namespace corotate
