// Linear tetrahedron (VTK "tetra" ordering). Reference coordinates (xi, eta, zeta)
// on the unit tet; N0 = 1 - xi - eta - zeta, N1 = xi, N2 = eta, N3 = zeta.
#pragma once

#include "corotate/elements/quadrature.hpp"

namespace corotate {

struct Tet4 {
  static constexpr int num_nodes = 4;
  static constexpr int dim = 3;  // a solid: reference coordinates span 3D
  static constexpr int num_stiffness_points = 1;  // points of stiffness_rule()
  static constexpr const char* name = "tetra";
  using ShapeValues = Eigen::Matrix<double, num_nodes, 1>;
  using ShapeGradient = Eigen::Matrix<double, num_nodes, 3>;  // row a = dN_a/dxi

  static ShapeValues shape(const Vec3& xi) { return ShapeValues(1 - xi.sum(), xi.x(), xi.y(), xi.z()); }
  static ShapeGradient shape_gradient(const Vec3&) {
    ShapeGradient g;
    g << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
    return g;
  }
  static Vec3 centre() { return Vec3::Constant(0.25); }
  // B is constant on a linear tet, so one point integrates K exactly; M is quadratic.
  static const QuadratureRule& stiffness_rule() {
    static const auto r = tet_centroid_rule();
    return r;
  }
  static const QuadratureRule& mass_rule() {
    static const auto r = tet_degree2_rule();
    return r;
  }
};

}  // namespace corotate
