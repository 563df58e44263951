// Sparse direct solve by Eigen's SimplicialLDLT (AMD ordering). The symbolic analysis is
// done once per pattern and reused; each solve factorizes numerically.
#pragma once

#include <Eigen/SparseCholesky>

#include "corotate/solvers/linear_solver.hpp"

namespace corotate {

class DirectSolver final : public LinearSolver {
 public:
  void reset() override { analysed_ = false; }
  // Projection keeps the pattern, and every solve factorizes numerically: nothing to forget.
  void constraints_changed(const FixedDofs&) override {}
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override;

 private:
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> scalar_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double, Eigen::ColMajor, int>> ldlt_;
  Vec residual_;
  bool analysed_ = false;
};

}  // namespace corotate
