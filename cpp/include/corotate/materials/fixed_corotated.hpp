// Fixed co-rotated elasticity (Stomakhin, Howes, Schroeder & Teran 2012):
//     W = mu |F - R|^2 + lambda/2 (J - 1)^2,   R = U V^T from the rotation-variant SVD,
//     P = 2 mu (F - R) + lambda (J - 1) cof F,
//     dP/dF = 2 mu (I - dR/dF) + lambda vec(cof F) vec(cof F)^T + lambda (J - 1) d2J/dF2.
// "Fixed" because the volume term uses J rather than the singular values of the original
// co-rotated model, which keeps an inverted element pushed back to J = 1 instead of towards
// a reflected rest shape. Defined for every F (inversion included); the Hessian is exact
// (dR/dF in closed form, see rotation_variant_svd.hpp) except where two singular values sum
// to zero, where R itself is not differentiable. At rest it equals linear elasticity with
// the Material's Lame parameters.
#pragma once

#include "corotate/materials/determinant_derivatives.hpp"
#include "corotate/materials/rotation_variant_svd.hpp"

namespace corotate {

struct FixedCorotated {
  static constexpr const char* name = "fixed_corotated";  // was "corotated" (see renamed_models)
  double lambda, mu;

  double energy(const Mat3& F) const {
    const RotationVariantSVD svd(F);
    const double J = F.determinant();
    // |F - R|^2 = sum (sigma_i - 1)^2 (U, V orthogonal).
    return mu * (svd.sigma.array() - 1).square().sum() + 0.5 * lambda * (J - 1) * (J - 1);
  }

  Mat3 stress(const Mat3& F) const {
    const RotationVariantSVD svd(F);
    return 2 * mu * (F - svd.rotation()) + lambda * (F.determinant() - 1) * cofactor(F);
  }

  Eigen::Matrix<double, 9, 9> tangent(const Mat3& F) const {
    const RotationVariantSVD svd(F);
    const double J = F.determinant();
    const Mat3 g = cofactor(F);
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> gv(g.data());
    Eigen::Matrix<double, 9, 9> A = (-2 * mu) * rotation_derivative(svd);
    A.diagonal().array() += 2 * mu;
    A.noalias() += lambda * gv * gv.transpose();
    A.noalias() += (lambda * (J - 1)) * determinant_hessian(F);
    return A;
  }
};

}  // namespace corotate
