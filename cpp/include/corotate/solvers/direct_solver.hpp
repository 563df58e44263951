// Sparse direct solve by Cholesky factorization (sparse_cholesky.hpp: SuiteSparse CHOLMOD
// when the build found it, else our own supernodal one). The symbolic analysis is done once
// per pattern and reused; each solve factorizes numerically, except one told that its matrix
// is the last one's (same_matrix_next: a step that kept its matrix), which solves with the
// last factor: the same answer to the bit, without the factorization that is most of a
// direct step.
#pragma once

#include "corotate/solvers/linear_solver.hpp"
#include "corotate/solvers/sparse_cholesky.hpp"

namespace corotate {

class DirectSolver final : public LinearSolver {
 public:
  explicit DirectSolver(SparseCholesky::Backend backend = SparseCholesky::Backend::Auto)
      : cholesky_(backend), coupled_cholesky_(backend) {}
  void reset() override {
    analysed_ = false;
    factorized_ = nullptr;
  }
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override;
  void same_matrix_next() override { same_matrix_next_ = true; }
  // Solves that used the last factor (same_matrix_next) instead of factorizing.
  long long factor_reuses() const { return factor_reuses_; }
  const char* backend_name() const { return cholesky_.backend_name(); }

 private:
  SolveStats solve_coupled(const BlockSparseMatrix& A, const Vec& b, Vec& x);
  static NotPositiveDefinite not_positive_definite();
  SparseCholesky::Matrix scalar_;
  SparseCholesky cholesky_;
  SparseCholesky coupled_cholesky_;  // of A + C, analysed at every coupled solve
  Vec residual_;
  bool analysed_ = false;
  const BlockSparseMatrix* factorized_ = nullptr;  // what cholesky_ holds the factor of
  bool same_matrix_next_ = false;
  long long factor_reuses_ = 0;
};

}  // namespace corotate
