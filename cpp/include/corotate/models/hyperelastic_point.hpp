// Energy, forces and exact stiffness that one quadrature point of a hyperelastic law adds
// to an element, from the shape-function gradients there (solids and membranes alike).
//
// x_e: 3 x N node positions; G: N x D, row a = dN_a/dX (D = 3 for solids, 2 for a membrane's
// rest plane); w: quadrature weight times the reference Jacobian (volume or area element).
// Then F = x_e G, the energy is w W(F), the nodal forces are f_a = -w P(F) G_a^T, and with
// vec(F) = D_G vec(x_e), D_G(i + 3j, 3a + i) = G(a, j), the stiffness is
//     K_e = w D_G^T (dP/dF) D_G,   block (a, b)_ik = w sum_jl G(a, j) G(b, l) A(i + 3j, k + 3l),
// evaluated without forming D_G.
#pragma once

#include "corotate/common.hpp"

namespace corotate {

template <int N, int D>
Eigen::Matrix<double, 3, D> deformation_gradient(const Eigen::Matrix<double, 3, N>& xe,
                                                 const Eigen::Matrix<double, N, D>& G) {
  return xe * G;
}

// fe -= w P G^T (fe: 3 x N element forces).
template <class Law, int N, int D>
void add_point_forces(const Law& law, const Eigen::Matrix<double, 3, D>& F, const Eigen::Matrix<double, N, D>& G,
                      double w, Eigen::Matrix<double, 3, N>& fe) {
  const Eigen::Matrix<double, 3, D> P = law.stress(F);
  fe.noalias() -= (w * P) * G.transpose();
}

// Ke += w D_G^T A D_G with A = dP/dF(F).
template <class Law, int N, int D>
void add_point_stiffness(const Law& law, const Eigen::Matrix<double, 3, D>& F, const Eigen::Matrix<double, N, D>& G,
                         double w, Eigen::Matrix<double, 3 * N, 3 * N>& Ke) {
  const Eigen::Matrix<double, 3 * D, 3 * D> A = law.tangent(F);
  // AG = A D_G (3D x 3N): column 3b + k is sum_l G(b, l) A.col(k + 3l).
  Eigen::Matrix<double, 3 * D, 3 * N> AG;
  for (int b = 0; b < N; ++b)
    for (int k = 0; k < 3; ++k) {
      auto col = AG.col(3 * b + k);
      col = G(b, 0) * A.col(k);
      for (int l = 1; l < D; ++l) col.noalias() += G(b, l) * A.col(k + 3 * l);
    }
  // Ke rows 3a..3a+2 += w sum_j G(a, j) AG rows 3j..3j+2.
  for (int a = 0; a < N; ++a)
    for (int j = 0; j < D; ++j)
      Ke.template middleRows<3>(3 * a).noalias() += (w * G(a, j)) * AG.template middleRows<3>(3 * j);
}

// Initial-stress (geometric) stiffness of one point: block (a, b) += w (G_a^T S G_b) I_3,
// with S the second Piola-Kirchhoff stress (D x D). Only the scalars G S G^T are returned
// (N x N); the caller spreads them on the block diagonals.
template <int N, int D>
Eigen::Matrix<double, N, N> point_geometric_stiffness(const Eigen::Matrix<double, D, D>& S,
                                                      const Eigen::Matrix<double, N, D>& G, double w) {
  return w * G * S * G.transpose();
}

}  // namespace corotate
