// What every element type gives the models, from its rest shape X (3 x N): the shape-function
// gradients and weights at the stiffness quadrature points, and its mass. Written once for
// the isoparametric solids (Tet4, Hex8, Hex20: reference coordinates in 3D) and for flat
// membrane elements (Tri3: reference coordinates in the element's rest plane), so a model
// kernel is written once for elements of any dimension.
#pragma once

#include <array>
#include <cmath>
#include <sstream>

#include "corotate/elements/hex20.hpp"
#include "corotate/elements/hex8.hpp"
#include "corotate/elements/tet4.hpp"
#include "corotate/elements/tri3.hpp"

namespace corotate {

template <class E>
using ElementNodes = Eigen::Matrix<double, 3, E::num_nodes>;  // 3 x N node coordinates

// One stiffness quadrature point: G = dN/dX (N x D, row a = dN_a/dX) and its weight
// w = Gauss weight x det J (x thickness for membranes), so that F = x_e G and the element
// energy is sum_q w_q W(F_q).
template <class E>
struct QuadraturePoint {
  Eigen::Matrix<double, E::num_nodes, E::dim> G;
  double w;
};
template <class E>
using QuadraturePoints = std::array<QuadraturePoint<E>, E::num_stiffness_points>;

// Consistent mass m_ab (the 3N x 3N matrix is m (x) I_3) and a lumped mass per node.
template <int N>
struct ElementMass {
  Eigen::Matrix<double, N, N> consistent;
  Eigen::Matrix<double, N, 1> lumped;
};

// Jacobian dX/dxi at a reference point of a solid, checked: an element whose Jacobian
// determinant is not clearly positive is degenerate (zero volume) or inverted, and is
// rejected by index.
template <class E>
Mat3 checked_jacobian(const ElementNodes<E>& X, const Vec3& xi, Index element) {
  const Mat3 J = X * E::shape_gradient(xi);
  const double extent = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).maxCoeff();
  const double det = J.determinant();
  if (!(det > 1e-10 * extent * extent * extent)) {
    std::ostringstream msg;
    msg << "element " << element << " (" << E::name << ") ";
    if (std::abs(det) <= 1e-10 * extent * extent * extent)
      msg << "has zero volume (degenerate: its nodes are coincident or coplanar)";
    else msg << "is inverted (negative Jacobian determinant " << det << "; check the node ordering)";
    throw InvalidInput(msg.str());
  }
  return J;
}

// thickness: of membrane elements [m]; solids ignore it.
template <class E>
QuadraturePoints<E> quadrature_points(const ElementNodes<E>& X, Index element, double thickness) {
  QuadraturePoints<E> points;
  if constexpr (E::dim == 2) {
    const typename E::Rest r = E::rest(X, element);
    points[0] = {r.G, thickness * r.area};
  } else {
    const QuadratureRule& rule = E::stiffness_rule();
    for (int q = 0; q < E::num_stiffness_points; ++q) {
      const Mat3 J = checked_jacobian<E>(X, rule.points[q], element);
      points[q] = {E::shape_gradient(rule.points[q]) * J.inverse(), rule.weights[q] * J.determinant()};
    }
  }
  return points;
}

template <class E>
ElementMass<E::num_nodes> element_mass(const ElementNodes<E>& X, Index element, double density, double thickness) {
  ElementMass<E::num_nodes> m;
  if constexpr (E::dim == 2) {
    const double total = density * thickness * E::rest(X, element).area;
    m.consistent = E::consistent_mass(total);
    m.lumped = E::lumped_mass(total);
  } else {
    m.consistent.setZero();
    for (size_t q = 0; q < E::mass_rule().points.size(); ++q) {
      const Vec3& xi = E::mass_rule().points[q];
      const double dV = E::mass_rule().weights[q] * checked_jacobian<E>(X, xi, element).determinant();
      const auto n = E::shape(xi);
      m.consistent.noalias() += (density * dV) * (n * n.transpose());
    }
    // Row-sum lumping; where a row sum is not positive (corner nodes of Hex20) use HRZ:
    // the consistent diagonal scaled so that the element keeps its total mass.
    m.lumped = m.consistent.rowwise().sum();
    if ((m.lumped.array() <= 0).any())
      m.lumped = m.consistent.diagonal() * (m.consistent.sum() / m.consistent.diagonal().sum());
  }
  return m;
}

}  // namespace corotate
