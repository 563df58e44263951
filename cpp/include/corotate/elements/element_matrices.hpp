// What every element type precomputes once from its rest shape and material:
// K_e = integral of B^T H B dV, the consistent mass, a lumped mass, the rest volume and
// the shape-function gradients at the element centre (for the deformation gradient F).
#pragma once

#include <sstream>

#include "corotate/elements/hex20.hpp"
#include "corotate/elements/hex8.hpp"
#include "corotate/elements/tet4.hpp"
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
    B(3, 3 * a + 1) = gz; B(3, 3 * a + 2) = gy;
    B(4, 3 * a) = gz;     B(4, 3 * a + 2) = gx;
    B(5, 3 * a) = gy;     B(5, 3 * a + 1) = gx;
  }
  return B;
}

// Jacobian dX/dxi at a reference point, checked: an element whose Jacobian determinant is
// not clearly positive is degenerate (zero volume) or inverted, and is rejected by index.
template <class E>
Mat3 checked_jacobian(const typename ElementMatrices<E>::NodeMatrix& X, const Vec3& xi, Index element) {
  const Mat3 J = X * E::shape_gradient(xi);
  const double extent = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).maxCoeff();
  const double det = J.determinant();
  if (!(det > 1e-10 * extent * extent * extent)) {
    std::ostringstream msg;
    msg << "element " << element << " (" << E::name << ") ";
    if (std::abs(det) <= 1e-10 * extent * extent * extent)
      msg << "has zero volume (degenerate: its nodes are coincident or coplanar)";
    else
      msg << "is inverted (negative Jacobian determinant " << det << "; check the node ordering)";
    throw InvalidInput(msg.str());
  }
  return J;
}

template <class E>
ElementMatrices<E> compute_element_matrices(const typename ElementMatrices<E>::NodeMatrix& X,
                                            const Material& material, Index element) {
  constexpr int N = E::num_nodes;
  using Gradient = typename ElementMatrices<E>::Gradient;
  ElementMatrices<E> out;
  const Eigen::Matrix<double, 6, 6> H = material.elasticity_matrix();

  out.stiffness.setZero();
  for (size_t q = 0; q < E::stiffness_rule().points.size(); ++q) {
    const Vec3& xi = E::stiffness_rule().points[q];
    const Mat3 J = checked_jacobian<E>(X, xi, element);
    const Gradient dN_dX = E::shape_gradient(xi) * J.inverse();
    const auto B = strain_displacement<N>(dN_dX);
    out.stiffness.noalias() += (E::stiffness_rule().weights[q] * J.determinant()) * (B.transpose() * H * B);
  }
  out.stiffness = 0.5 * (out.stiffness + out.stiffness.transpose()).eval();  // exact symmetry

  out.mass.setZero();
  out.volume = 0;
  for (size_t q = 0; q < E::mass_rule().points.size(); ++q) {
    const Vec3& xi = E::mass_rule().points[q];
    const double dV = E::mass_rule().weights[q] * checked_jacobian<E>(X, xi, element).determinant();
    const auto n = E::shape(xi);
    out.mass.noalias() += (material.density * dV) * (n * n.transpose());
    out.volume += dV;
  }

  // Row-sum lumping; where a row sum is not positive (corner nodes of Hex20) use HRZ:
  // the consistent diagonal scaled so that the element keeps its total mass.
  out.lumped_mass = out.mass.rowwise().sum();
  if ((out.lumped_mass.array() <= 0).any())
    out.lumped_mass = out.mass.diagonal() * (out.mass.sum() / out.mass.diagonal().sum());

  const Vec3 centre = E::centre();
  out.centre_gradient = E::shape_gradient(centre) * checked_jacobian<E>(X, centre, element).inverse();
  return out;
}

}  // namespace corotate
