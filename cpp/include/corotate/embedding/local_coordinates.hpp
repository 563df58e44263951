// Where a point lies in one element: its local coordinates, the shape-function weights that
// reproduce it from the element's nodes, and the paper's criterion (§2.2.2) of how far
// outside the element it is, zero inside.
//   Tet4: barycentric coordinates (N0..N3), criterion sum |N_a| - 1 (the paper's sum of
//         absolute local coordinates, shifted so that it vanishes inside).
//   Hex8, Hex20: natural coordinates xi from the inverse isoparametric map, by Newton's
//         method; criterion sum_i max(0, |xi_i| - 1), the excess outside [-1, 1]^3.
#pragma once

#include <cmath>
#include <limits>

#include "corotate/elements/element_geometry.hpp"

namespace corotate {

template <class E>
struct PointInElement {
  Vec3 xi = Vec3::Zero();  // reference coordinates (Tet4: N1..N3, i.e. xi, eta, zeta)
  typename E::ShapeValues weights;  // N_a(xi): the point is sum_a N_a X_a
  double criterion = std::numeric_limits<double>::infinity();  // 0 inside; inf: no answer
  // The same element point with xi clamped into the element (for the distance report).
  Vec3 clamped_point = Vec3::Zero();
};

// What an element keeps for the inverse map, computed once from its rest nodes X (3 x N).
template <class E>
struct ElementInverseMap {
  ElementNodes<E> X;
  Mat3 inverse_edges = Mat3::Identity();  // Tet4: [X1 - X0, X2 - X0, X3 - X0]^-1 (unused by hexes)
  double size = 0;  // longest edge of the element's bounding box

  ElementInverseMap() = default;
  explicit ElementInverseMap(const ElementNodes<E>& rest) : X(rest) {
    size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).maxCoeff();
    if constexpr (E::num_nodes == 4) {
      Mat3 D;
      D << X.col(1) - X.col(0), X.col(2) - X.col(0), X.col(3) - X.col(0);
      inverse_edges = D.inverse();
    }
  }

  PointInElement<E> locate(const Vec3& p) const {
    PointInElement<E> r;
    if constexpr (E::num_nodes == 4) {
      r.xi = inverse_edges * (p - X.col(0));
      r.weights = E::shape(r.xi);
      r.criterion = std::max(r.weights.cwiseAbs().sum() - 1.0, 0.0);
      typename E::ShapeValues w = r.weights.cwiseMax(0.0);
      r.clamped_point = X * (w / w.sum());
    } else {
      // Newton on X N(xi) = p from the centre. Far outside a curved Hex20 the map may have no
      // preimage or several; the iterate is kept in a box of 4 element widths, and a point
      // where it does not converge gets no answer (criterion inf) from this element.
      Vec3 xi = Vec3::Zero();
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
      r.xi = xi;
      r.weights = E::shape(xi);
      r.criterion = (xi.cwiseAbs().array() - 1.0).cwiseMax(0.0).sum();
      r.clamped_point = X * E::shape(xi.cwiseMax(-1.0).cwiseMin(1.0));
    }
    return r;
  }
};

}  // namespace corotate
