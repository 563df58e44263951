// Projection of a symmetric element Hessian onto the positive semi-definite cone (the
// nearest PSD matrix in the Frobenius norm): clamp negative eigenvalues to zero.
// Why: an indefinite element Hessian (compressed StVK, inverted Neo-Hookean, ...) can make
// the assembled Newton matrix indefinite, where CG breaks down and a Newton step may go
// uphill. Projected per element, the sum is PSD and every step is a descent direction.
// A matrix that is already PSD is returned untouched (bit for bit). "Already PSD" allows for
// rounding: element stiffnesses have exact zero eigenvalues (rigid-body modes) that come out
// of the eigen solver as +-1e-16 |K|, and clamping those would only add noise.
#pragma once

#include <Eigen/Eigenvalues>

#include "corotate/common.hpp"

namespace corotate {

template <int N>
void project_psd(Eigen::Matrix<double, N, N>& K) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(K);
  const double tolerance = 1e-12 * eig.eigenvalues().cwiseAbs().maxCoeff();
  if (eig.eigenvalues().minCoeff() >= -tolerance) return;
  K = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace corotate
