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
  if (!coupling_) {
    cholesky_.solve(b, x);
    return {0, relative_residual(A, b, x, residual_), true};
  }
  return solve_coupled(A, b, x);
}

// (A + C) x = b by CG preconditioned with A's factor: C (contact between parts of a body)
// couples few nodes, so the factor leaves few directions for CG to find.
SolveStats DirectSolver::solve_coupled(const BlockSparseMatrix& A, const Vec& b, Vec& x) {
  const auto apply = [&](const Vec& v, Vec& out) {
    A.multiply(v, out);
    coupling_->multiply_add(v, out);
  };
  const double b_norm = b.norm();
  x.setZero(b.size());
  if (b_norm == 0) return {0, 0.0, true};
  const double target = 1e-12 * b_norm;
  Vec r = b, z(b.size()), p, q(b.size());
  cholesky_.solve(r, z);
  p = z;
  double rz = r.dot(z), r_norm = b_norm;
  int it = 0;
  for (; it < 500 && r_norm > target; ++it) {
    apply(p, q);
    const double pq = p.dot(q);
    if (!(pq > 0)) throw NotPositiveDefinite("direct solver: the coupled system is not positive definite");
    const double alpha = rz / pq;
    x += alpha * p;
    r -= alpha * q;
    r_norm = r.norm();
    cholesky_.solve(r, z);
    const double rz_new = r.dot(z);
    p = z + (rz_new / rz) * p;
    rz = rz_new;
  }
  return {it, r_norm / b_norm, r_norm <= target};
}

}  // namespace corotate
