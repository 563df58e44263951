// Rotation-variant SVD of a 3 x 3 matrix: F = U diag(sigma) V^T with U, V proper rotations
// (det = +1) and sigma sorted by magnitude, the last one negative when det F < 0.
// This is what the fixed co-rotated energy needs: R = U V^T is then the closest rotation
// to F even for an inverted F (a plain SVD would give a reflection), and the derivative of
// R has the closed form of rotation_derivative below.
#pragma once

#include <Eigen/SVD>

#include "corotate/common.hpp"

namespace corotate {

struct RotationVariantSVD {
  Mat3 U, V;
  Vec3 sigma;

  explicit RotationVariantSVD(const Mat3& F) {
    const Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
    U = svd.matrixU();
    V = svd.matrixV();
    sigma = svd.singularValues();  // descending, >= 0
    // Move reflections into the smallest singular value.
    if (U.determinant() < 0) {
      U.col(2) *= -1;
      sigma(2) *= -1;
    }
    if (V.determinant() < 0) {
      V.col(2) *= -1;
      sigma(2) *= -1;
    }
  }

  Mat3 rotation() const { return U * V.transpose(); }
};

// d vec(R) / d vec(F) for R = U V^T (column-major vec, 9 x 9).
// With A = U^T dF V, U^T dR V is skew with entries (A_ij - A_ji) / (sigma_i + sigma_j), so
// dR/dF = sum over the pairs (i, j) of 2 / (sigma_i + sigma_j) t t^T with the unit "twist"
// t = vec(U (e_i e_j^T - e_j e_i^T) V^T) / sqrt(2) (Kim & Eberle, Dynamic Deformables, 2020).
// sigma_i + sigma_j >= 0 always; it vanishes only when F is flattened so that R is not
// unique (the derivative is infinite there), and is clamped to keep the result finite.
inline Eigen::Matrix<double, 9, 9> rotation_derivative(const RotationVariantSVD& svd) {
  Eigen::Matrix<double, 9, 9> dR = Eigen::Matrix<double, 9, 9>::Zero();
  const double floor = 1e-12 * std::max(1.0, std::abs(svd.sigma(0)));
  static const int pairs[3][2] = {{1, 2}, {0, 2}, {0, 1}};
  for (const auto& p : pairs) {
    const int i = p[0], j = p[1];
    const Mat3 T = (svd.U.col(i) * svd.V.col(j).transpose() - svd.U.col(j) * svd.V.col(i).transpose()) / std::sqrt(2.0);
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> t(T.data());
    dR.noalias() += (2 / std::max(svd.sigma(i) + svd.sigma(j), floor)) * t * t.transpose();
  }
  return dR;
}

}  // namespace corotate
