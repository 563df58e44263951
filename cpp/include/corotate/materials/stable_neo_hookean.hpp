// Compressible Neo-Hookean in the stable form of Smith, de Goes & Kim 2018, "Stable
// Neo-Hookean Flesh Simulation" (their eq. with alpha = 1 + mu/lambda', without the optional
// -mu/2 log(I_C + 1) term):
//     W = mu/2 (I_C - 3) - mu (J - 1) + lambda'/2 (J - 1)^2,   I_C = |F|^2,  J = det F,
//     P = mu F + (lambda' (J - 1) - mu) cof F,
//     dP/dF = mu I + lambda' vec(cof F) vec(cof F)^T + (lambda' (J - 1) - mu) d2J/dF2.
// Why this form and not mu/2 (I_C - 3) - mu log J + lambda/2 log^2 J: it has no log J, so
// energy, force and Hessian are finite and smooth for every F, including degenerate (J = 0)
// and inverted (J < 0) elements, which then feel a force pushing them back towards J = 1. A
// Newton step that overshoots into inversion therefore never produces NaN and nothing has to
// be rejected; the classic form would need J > 0 everywhere.
//
// Parameters: lambda' = lambda + mu, with lambda, mu the Lame parameters of the Material.
// Then P(I) = 0 and the linearisation at rest is mu (dF + dF^T) + lambda tr(dF) I, exactly
// linear elasticity, so small-strain answers agree with the linear and co-rotational models.
#pragma once

#include "corotate/materials/determinant_derivatives.hpp"

namespace corotate {

struct StableNeoHookean {
  static constexpr const char* name = "neohookean";
  double lambda, mu;  // Lame parameters of the Material (lambda' = lambda + mu is internal)

  double energy(const Mat3& F) const {
    const double J = F.determinant(), lp = lambda + mu;
    return 0.5 * mu * (F.squaredNorm() - 3) - mu * (J - 1) + 0.5 * lp * (J - 1) * (J - 1);
  }

  Mat3 stress(const Mat3& F) const {
    const double J = F.determinant(), lp = lambda + mu;
    return mu * F + (lp * (J - 1) - mu) * cofactor(F);
  }

  Eigen::Matrix<double, 9, 9> tangent(const Mat3& F) const {
    const double J = F.determinant(), lp = lambda + mu;
    const Mat3 g = cofactor(F);
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> gv(g.data());
    Eigen::Matrix<double, 9, 9> A = (lp * (J - 1) - mu) * determinant_hessian(F);
    A.noalias() += lp * gv * gv.transpose();
    A.diagonal().array() += mu;
    return A;
  }
};

}  // namespace corotate
