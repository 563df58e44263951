// LU with partial pivoting for small dense systems (tens of unknowns), done column by column
// (right-looking rank-one updates, dense_kernels.cpp, compiled per instruction-set level).
// Eigen's PartialPivLU blocks every matrix above 16 x 16 (a panel of 8 columns, then general
// matrix products that pack their operands), which at the 26 x 26 of a 20-mode floating-frame
// step takes 3.7 us against 1.9 us here (AVX2 EPYC; the solves 0.48 against 0.45 us). The
// factor is kept in place of the matrix; no allocation once sized.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "corotate/common.hpp"
#include "corotate/solvers/dense_kernels.hpp"

namespace corotate {

class SmallDenseLU {
 public:
  Index rows() const { return lu_.rows(); }

  // Factors A (square). False when a pivot is zero or not finite (A singular or not finite);
  // solve() must not be called then.
  bool compute(const Eigen::Ref<const Eigen::MatrixXd>& A) {
    lu_ = A;
    swaps_.resize(lu_.rows());
    return factor_lu(lu_.data(), int(lu_.rows()), swaps_.data());
  }

  // x = A^-1 b.
  void solve(const Vec& b, Vec& x) const {
    x = b;
    solve_lu(lu_.data(), int(lu_.rows()), swaps_.data(), x.data());
  }

 private:
  Eigen::MatrixXd lu_;
  std::vector<int> swaps_;  // row k was swapped with row swaps_[k] at step k
};

}  // namespace corotate
