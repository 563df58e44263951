// The linear element matrices of a solid from its rest shape and material:
// K_e = integral of B^T H B dV, the consistent and lumped mass, the rest volume and the
// shape-function gradients at the element centre (for the deformation gradient F).
// Used by the linear and co-rotational kernels (which need K_e) and by tests.
#pragma once

#include "corotate/elements/element_geometry.hpp"
#include "corotate/material.hpp"

namespace corotate {

template <class E>
struct ElementMatrices {
  static constexpr int N = E::num_nodes;
  using NodeMatrix = Eigen::Matrix<double, 3, N>;        // 3 x N element node coordinates
  using Stiffness = Eigen::Matrix<double, 3 * N, 3 * N>;  // DOF order 3*a + axis
  using Gradient = Eigen::Matrix<double, N, 3>;           // row a = dN_a/dX

  Stiffness stiffness;
  Eigen::Matrix<double, N, N> mass;  // consistent mass m_ab; the 3N x 3N matrix is m (x) I_3
  Eigen::Matrix<double, N, 1> lumped_mass;
  Gradient centre_gradient;  // F = x_e * centre_gradient (for Tet4 this is Ds Dm^-1)
  double volume = 0;
};

// Strain-displacement matrix in Voigt order (xx, yy, zz, yz, xz, xy), engineering shear.
template <int N>
Eigen::Matrix<double, 6, 3 * N> strain_displacement(const Eigen::Matrix<double, N, 3>& dN_dX) {
  Eigen::Matrix<double, 6, 3 * N> B = Eigen::Matrix<double, 6, 3 * N>::Zero();
  for (int a = 0; a < N; ++a) {
    const double gx = dN_dX(a, 0), gy = dN_dX(a, 1), gz = dN_dX(a, 2);
    B(0, 3 * a) = gx;
    B(1, 3 * a + 1) = gy;
    B(2, 3 * a + 2) = gz;
    B(3, 3 * a + 1) = gz;
    B(3, 3 * a + 2) = gy;
    B(4, 3 * a) = gz;
    B(4, 3 * a + 2) = gx;
    B(5, 3 * a) = gy;
    B(5, 3 * a + 1) = gx;
  }
  return B;
}

// K_e = sum_q w_q B_q^T H B_q (exactly symmetric).
template <class E>
typename ElementMatrices<E>::Stiffness linear_stiffness(const QuadraturePoints<E>& points, const Material& material) {
  const Eigen::Matrix<double, 6, 6> H = material.elasticity_matrix();
  typename ElementMatrices<E>::Stiffness K = ElementMatrices<E>::Stiffness::Zero();
  for (const auto& p : points) {
    const auto B = strain_displacement<E::num_nodes>(p.G);
    K.noalias() += p.w * (B.transpose() * H * B);
  }
  return 0.5 * (K + K.transpose());
}

// dN/dX at the element centre (F there = x_e * this).
template <class E>
typename ElementMatrices<E>::Gradient centre_gradient(const ElementNodes<E>& X, Index element) {
  const Vec3 centre = E::centre();
  return E::shape_gradient(centre) * checked_jacobian<E>(X, centre, element).inverse();
}

template <class E>
ElementMatrices<E> compute_element_matrices(const ElementNodes<E>& X, const Material& material, Index element) {
  ElementMatrices<E> out;
  out.stiffness = linear_stiffness<E>(quadrature_points<E>(X, element, 1.0), material);
  const ElementMass<E::num_nodes> m = element_mass<E>(X, element, material.density, 1.0);
  out.mass = m.consistent;
  out.lumped_mass = m.lumped;
  out.volume = m.consistent.sum() / material.density;
  out.centre_gradient = centre_gradient<E>(X, element);
  return out;
}

}  // namespace corotate
