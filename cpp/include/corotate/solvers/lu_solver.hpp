// Sparse direct solve of a general (non-symmetric) system by Eigen's supernodal SparseLU
// (COLAMD ordering, partial pivoting), for the non-symmetric exact tangent of co-rotated hexes
// (ForceModel::symmetric_tangent() false). The symbolic analysis is done once per pattern and
// reused; each solve factorizes numerically. On the hexahedral meshes of the tests it is as
// fast as the SimplicialLDLT of DirectSolver (supernodes make up for the pivoting). With a
// coupling (contacts between nodes outside the pattern) it factorizes A + C
// (coupled_matrix.hpp), analysed afresh each time.
#pragma once

#include <Eigen/SparseLU>

#include "corotate/solvers/linear_solver.hpp"

namespace corotate {

class LuSolver final : public LinearSolver {
 public:
  void reset() override { analysed_ = false; }
  // Throws SolverFailure when A is singular.
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override;

 private:
  using ScalarMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  ScalarMatrix rows_;  // the CSR arrays of A, that is A^T in column-major storage
  ScalarMatrix scalar_;
  Eigen::SparseLU<ScalarMatrix, Eigen::COLAMDOrdering<int>> lu_;
  Eigen::SparseLU<ScalarMatrix, Eigen::COLAMDOrdering<int>> coupled_lu_;
  Vec residual_;
  bool analysed_ = false;
};

}  // namespace corotate
