// The classic compressible Neo-Hookean law with a logarithmic volume term (Bonet & Wood,
// "Nonlinear Continuum Mechanics for Finite Element Analysis", eq. 6.27; the "neo-Hookean"
// of FEBio and most engineering codes, the reference their results are quoted in):
//     W = mu/2 (I_C - 3) - mu ln J + lambda/2 (ln J)^2,   I_C = |F|^2,  J = det F,
//     P = mu (F - F^-T) + lambda ln J F^-T,
//     dP = mu dF + (mu - lambda ln J) F^-T dF^T F^-T + lambda tr(F^-1 dF) F^-T,
// using d(F^-T) = -F^-T dF^T F^-T and d ln J = tr(F^-1 dF). At rest P = 0 and dP is linear
// elasticity with the Material's Lame parameters. W grows without bound as J -> 0, so it
// resists crushing better than StVK; it is undefined for J <= 0: there the energy is +inf
// (a line search backs away) and stress and tangent are NaN (a step fails with a clear error
// and restores the state). For simulations that must pass through inversion use
// "neohookean" (stable_neo_hookean.hpp).
#pragma once

#include <limits>

#include "corotate/common.hpp"

namespace corotate {

struct LogNeoHookean {
  static constexpr const char* name = "neohookean_log";
  double lambda, mu;

  double energy(const Mat3& F) const {
    const double J = F.determinant();
    if (!(J > 0)) return std::numeric_limits<double>::infinity();
    const double lnJ = std::log(J);
    return 0.5 * mu * (F.squaredNorm() - 3) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
  }

  Mat3 stress(const Mat3& F) const {
    const double J = F.determinant();
    if (!(J > 0)) return Mat3::Constant(std::numeric_limits<double>::quiet_NaN());
    const Mat3 FinvT = F.inverse().transpose();
    return mu * (F - FinvT) + lambda * std::log(J) * FinvT;
  }

  // Column c = i + 3 j of dvec(P)/dvec(F) is dP for dF = e_i e_j^T:
  //   F^-T dF^T F^-T = (column j of F^-T)(row i of F^-T), tr(F^-1 dF) = F^-T(i, j).
  Eigen::Matrix<double, 9, 9> tangent(const Mat3& F) const {
    const double J = F.determinant();
    if (!(J > 0)) return Eigen::Matrix<double, 9, 9>::Constant(std::numeric_limits<double>::quiet_NaN());
    const Mat3 G = F.inverse().transpose();  // F^-T
    const double c = mu - lambda * std::log(J);
    Eigen::Matrix<double, 9, 9> A;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        Mat3 dP = c * G.col(j) * G.row(i) + (lambda * G(i, j)) * G;
        dP(i, j) += mu;
        A.col(i + 3 * j) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
      }
    return A;
  }
};

}  // namespace corotate
