// Two-level (smoothed-aggregation) preconditioner for meshes too large to factorize.
//
// Nodes are grouped into aggregates of a node and its neighbours. Each aggregate's coarse
// space is its six rigid-body modes (three translations, three infinitesimal rotations), the
// near-kernel of elasticity that a point smoother cannot reduce. The tentative prolongator
// is smoothed once by damped Jacobi, P = (I - w D^-1 A0) P_tent, and the coarse matrix
// Pc = P^T A0 P of the first system it sees (the rest state) is factorized once. Each
// application is a symmetric V(1,1) cycle: damped block-Jacobi smoothing with the current
// matrix, coarse correction with the fixed factor, smoothing again. Setup costs a few
// sparse products instead of a fine-level factorization whose fill grows as n^(4/3) or
// worse; an application costs three matrix-vector products' worth of work.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

#include "corotate/solvers/preconditioner.hpp"
#include "corotate/solvers/sparse_cholesky.hpp"

namespace corotate {

class TwoLevelPreconditioner final : public Preconditioner {
 public:
  void reset() override { ready_ = false; }
  // Rest positions (3 x n): the rotation modes of each aggregate are built from them.
  void set_geometry(const Nodes& rest) override {
    rest_ = rest;
    ready_ = false;
  }
  void compute(const BlockSparseMatrix& A) override;
  void apply(const Vec& r, Vec& z) override;
  Index coarse_size() const { return coarse_.rows(); }

 private:
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  void setup(const BlockSparseMatrix& A0);
  void smooth(const Vec& r, Vec& z);  // z = w D^-1 r (block diagonal of the current A)

  Nodes rest_;
  bool ready_ = false;
  const BlockSparseMatrix* A_ = nullptr;  // current system matrix (set by compute)
  BlockJacobiPreconditioner diagonal_;
  SparseMatrix prolongation_, restriction_;  // P (3n x 6m) and P^T
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> coarse_;
  SparseCholesky coarse_factor_;  // CHOLMOD when built with it
  Vec residual_, coarse_rhs_, coarse_solution_, correction_;
  double smoothing_weight_ = 0.0;  // 4 / (3 lambda_max(D^-1 A0)): the smoother contracts
};

}  // namespace corotate
