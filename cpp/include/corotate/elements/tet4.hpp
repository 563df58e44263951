// Linear tetrahedron (VTK "tetra" ordering). Reference coordinates (xi, eta, zeta)
// on the unit tet; N0 = 1 - xi - eta - zeta, N1 = xi, N2 = eta, N3 = zeta.
// Its facts (element_topology.hpp): nodes 0, 1, 2 counter-clockwise seen from node 3.
#pragma once

#include "corotate/elements/element_topology.hpp"
#include "corotate/elements/quadrature.hpp"

namespace corotate {

struct Tet4 {
  static constexpr const char* name = "tetra";
  static constexpr const char* generator_name = "tet4";
  static constexpr ReferenceDomain domain = ReferenceDomain::simplex;
  static constexpr int dim = 3;  // a solid: reference coordinates span 3D
  static constexpr int order = 1;
  static constexpr int num_nodes = 4;
  static constexpr int num_corners = 4;
  static constexpr int num_stiffness_points = 1;  // points of stiffness_rule()
  // In VTK's tetra10 mid-node order.
  static constexpr std::array<std::array<int, 2>, 6> edges = {{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};
  static constexpr std::array<std::array<int, 3>, 4> faces = {{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}};
  static constexpr std::array<int, 4> corner_mirror = {0, 2, 1, 3};
  using ShapeValues = Eigen::Matrix<double, num_nodes, 1>;
  using ShapeGradient = Eigen::Matrix<double, num_nodes, 3>;  // row a = dN_a/dxi

  static Vec3 node(int a) { return a == 0 ? Vec3::Zero() : Vec3(Vec3::Unit(a - 1)); }
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
