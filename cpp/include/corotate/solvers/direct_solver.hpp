// Sparse direct solve by Cholesky factorization (sparse_cholesky.hpp: SuiteSparse CHOLMOD
// when the build found it, else Eigen's SimplicialLDLT). The symbolic analysis is done once
// per pattern and reused; each solve factorizes numerically.
#pragma once

#include "corotate/solvers/linear_solver.hpp"
#include "corotate/solvers/sparse_cholesky.hpp"

namespace corotate {

class DirectSolver final : public LinearSolver {
 public:
  explicit DirectSolver(SparseCholesky::Backend backend = SparseCholesky::Backend::Auto)
      : cholesky_(backend), coupled_cholesky_(backend) {}
  void reset() override { analysed_ = false; }
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override;
  const char* backend_name() const { return cholesky_.backend_name(); }

 private:
  SolveStats solve_coupled(const BlockSparseMatrix& A, const Vec& b, Vec& x);
  static NotPositiveDefinite not_positive_definite();
  SparseCholesky::Matrix scalar_;
  SparseCholesky cholesky_;
  SparseCholesky coupled_cholesky_;  // of A + C, analysed at every coupled solve
  Vec residual_;
  bool analysed_ = false;
};

}  // namespace corotate
