// LU with partial pivoting for small dense systems (tens of unknowns), done column by column
// (right-looking rank-one updates). Eigen's PartialPivLU blocks every matrix above 16 x 16 (a
// panel of 8 columns, then general matrix products that pack their operands), which at the
// 26 x 26 of a 20-mode floating-frame step takes 3.65 us against 2.3 us here (AVX2 EPYC, the
// library's x86-64 baseline code; the solves take the same 0.49 us). The factor is kept in
// place of the matrix; no allocation once sized.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

class SmallDenseLU {
 public:
  Index rows() const { return lu_.rows(); }

  // Factors A (square). False when a pivot is zero or not finite (A singular or not finite);
  // solve() must not be called then.
  bool compute(const Eigen::Ref<const Eigen::MatrixXd>& A) {
    lu_ = A;
    const Index n = lu_.rows();
    swaps_.resize(n);
    for (Index k = 0; k < n; ++k) {
      Index p = 0;
      const double pivot = lu_.col(k).tail(n - k).cwiseAbs().maxCoeff(&p);
      p += k;
      swaps_[k] = p;
      if (!(pivot > 0.0) || !std::isfinite(pivot)) return false;
      if (p != k) lu_.row(k).swap(lu_.row(p));
      const Index rest = n - k - 1;
      lu_.col(k).tail(rest) /= lu_(k, k);
      lu_.bottomRightCorner(rest, rest).noalias() -= lu_.col(k).tail(rest) * lu_.row(k).tail(rest);
    }
    return true;
  }

  // x = A^-1 b (x may be b).
  void solve(const Vec& b, Vec& x) const {
    x = b;
    for (Index k = 0; k < lu_.rows(); ++k)
      if (swaps_[k] != k) std::swap(x[k], x[swaps_[k]]);
    lu_.triangularView<Eigen::UnitLower>().solveInPlace(x);
    lu_.triangularView<Eigen::Upper>().solveInPlace(x);
  }

 private:
  Eigen::MatrixXd lu_;
  std::vector<Index> swaps_;  // row k was swapped with row swaps_[k] at step k
};

}  // namespace corotate
