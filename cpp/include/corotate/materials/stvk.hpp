// St. Venant-Kirchhoff: the linear isotropic law applied to the Green strain,
//     E = (F^T F - I) / 2,   W = mu E:E + lambda/2 tr(E)^2,
//     S = 2 mu E + lambda tr(E) I   (second Piola-Kirchhoff),   P = F S   (first).
// Exact under any rigid motion and equal to linear elasticity at small strain, but it
// softens under strong compression (W falls back to zero as an element is flattened), so
// it is the reference for moderate strains, not for crushing.
//
// Written for F of 3 x D: D = 3 for solids, D = 2 for membranes (F maps the element's 2D
// rest plane into space; E, S are then 2 x 2 and lambda should be the plane-stress value).
// Vectorised quantities use column-major vec: vec(F)[i + 3 j] = F(i, j).
#pragma once

#include "corotate/common.hpp"

namespace corotate {

struct StVK {
  static constexpr const char* name = "stvk";
  double lambda, mu;

  template <int D>
  Eigen::Matrix<double, D, D> green_strain(const Eigen::Matrix<double, 3, D>& F) const {
    Eigen::Matrix<double, D, D> E = 0.5 * F.transpose() * F;
    E.diagonal().array() -= 0.5;
    return E;
  }

  template <int D>
  Eigen::Matrix<double, D, D> second_piola(const Eigen::Matrix<double, 3, D>& F) const {
    const Eigen::Matrix<double, D, D> E = green_strain(F);
    Eigen::Matrix<double, D, D> S = (2 * mu) * E;
    S.diagonal().array() += lambda * E.trace();
    return S;
  }

  template <int D>
  double energy(const Eigen::Matrix<double, 3, D>& F) const {
    const Eigen::Matrix<double, D, D> E = green_strain(F);
    const double tr = E.trace();
    return mu * E.squaredNorm() + 0.5 * lambda * tr * tr;
  }

  template <int D>
  Eigen::Matrix<double, 3, D> stress(const Eigen::Matrix<double, 3, D>& F) const {
    return F * second_piola(F);
  }

  // dvec(P)/dvec(F), 3D x 3D. dP = dF S + F dS with dS = 2 mu sym(F^T dF) + lambda tr(F^T dF) I;
  // one column per unit direction dF = e_i e_j^T (symmetric: W is a potential).
  template <int D>
  Eigen::Matrix<double, 3 * D, 3 * D> tangent(const Eigen::Matrix<double, 3, D>& F) const {
    const Eigen::Matrix<double, D, D> S = second_piola(F);
    Eigen::Matrix<double, 3 * D, 3 * D> A;
    for (int c = 0; c < 3 * D; ++c) {
      const int i = c % 3, j = c / 3;
      // F^T dF has only column j, equal to row i of F.
      Eigen::Matrix<double, D, D> FtdF = Eigen::Matrix<double, D, D>::Zero();
      FtdF.col(j) = F.row(i).transpose();
      Eigen::Matrix<double, D, D> dS = mu * (FtdF + FtdF.transpose());
      dS.diagonal().array() += lambda * FtdF(j, j);
      Eigen::Matrix<double, 3, D> dP = F * dS;
      dP.row(i) += S.row(j);  // dF S = e_i (row j of S)
      A.col(c) = Eigen::Map<const Eigen::Matrix<double, 3 * D, 1>>(dP.data());
    }
    return A;
  }
};

}  // namespace corotate
