// Where a point lies in one element: its local coordinates, the shape-function weights that
// reproduce it from the element's nodes, and the paper's criterion (§2.2.2) of how far
// outside the element it is, zero inside.
// The reference domain of the element (element_topology.hpp) decides the criterion:
//   simplex (Tet4, Tet10): barycentric coordinates L of xi, criterion sum |L_a| - 1 (the
//         paper's sum of absolute local coordinates, shifted so that it vanishes inside);
//   cube (Hex8, Hex20): criterion sum_i max(0, |xi_i| - 1), the excess outside [-1, 1]^3.
// Linear simplices (Tet4) invert their affine map in closed form; every other element finds
// xi from the inverse isoparametric map by Newton's method.
#pragma once

#include <cmath>
#include <limits>

#include "corotate/elements/element_geometry.hpp"

namespace corotate {

// Barycentric coordinates of a point xi of the reference simplex.
inline Eigen::Vector4d barycentric(const Vec3& xi) { return {1 - xi.sum(), xi.x(), xi.y(), xi.z()}; }

// The paper's criterion (0 inside) and xi moved onto the closest point of the reference cell
// in its own coordinates (for the distance report).
template <ReferenceDomain D>
double outside_criterion(const Vec3& xi) {
  if constexpr (D == ReferenceDomain::simplex) return std::max(barycentric(xi).cwiseAbs().sum() - 1.0, 0.0);
  else return (xi.cwiseAbs().array() - 1.0).cwiseMax(0.0).sum();
}
template <ReferenceDomain D>
Vec3 clamped_into_cell(const Vec3& xi) {
  if constexpr (D == ReferenceDomain::simplex) {
    const Eigen::Vector4d L = barycentric(xi).cwiseMax(0.0);
    return L.tail<3>() / L.sum();
  } else {
    return xi.cwiseMax(-1.0).cwiseMin(1.0);
  }
}

template <class E>
struct PointInElement {
  Vec3 xi = Vec3::Zero();  // reference coordinates (simplices: L1..L3, i.e. xi, eta, zeta)
  typename E::ShapeValues weights;  // N_a(xi): the point is sum_a N_a X_a
  double criterion = std::numeric_limits<double>::infinity();  // 0 inside; inf: no answer
  // The same element point with xi clamped into the element (for the distance report).
  Vec3 clamped_point = Vec3::Zero();
};

// What an element keeps for the inverse map, computed once from its rest nodes X (3 x N).
template <class E>
struct ElementInverseMap {
  ElementNodes<E> X;
  // Affine elements: [X1 - X0, X2 - X0, X3 - X0]^-1 (unused by the others).
  Mat3 inverse_edges = Mat3::Identity();
  static constexpr bool affine = E::domain == ReferenceDomain::simplex && E::order == 1;
  double size = 0;  // longest edge of the element's bounding box

  ElementInverseMap() = default;
  explicit ElementInverseMap(const ElementNodes<E>& rest) : X(rest) {
    size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).maxCoeff();
    if constexpr (affine) {
      Mat3 D;
      D << X.col(1) - X.col(0), X.col(2) - X.col(0), X.col(3) - X.col(0);
      inverse_edges = D.inverse();
    }
  }

  PointInElement<E> locate(const Vec3& p) const {
    PointInElement<E> r;
    Vec3 xi = E::centre();
    if constexpr (affine) {
      xi = inverse_edges * (p - X.col(0));
    } else {
      // Newton on X N(xi) = p from the centre. Far outside a curved element the map may have
      // no preimage or several; the iterate is kept in a box of 4 element widths, and a point
      // where it does not converge gets no answer (criterion inf) from this element.
      bool converged = false;
      for (int it = 0; it < 30 && !converged; ++it) {
        const Vec3 residual = X * E::shape(xi) - p;
        const Mat3 J = X * E::shape_gradient(xi);
        const Vec3 step = J.partialPivLu().solve(residual);
        if (!step.allFinite()) break;
        xi = (xi - step).cwiseMax(-4.0).cwiseMin(4.0);
        converged = step.cwiseAbs().maxCoeff() < 1e-13;
      }
      if (!converged) {
        // One last check: a step just above the threshold can still be at round-off.
        if (!((X * E::shape(xi) - p).norm() <= 1e-12 * size)) return r;
      }
    }
    r.xi = xi;
    r.weights = E::shape(xi);
    r.criterion = outside_criterion<E::domain>(xi);
    r.clamped_point = X * E::shape(clamped_into_cell<E::domain>(xi));
    return r;
  }
};

}  // namespace corotate
