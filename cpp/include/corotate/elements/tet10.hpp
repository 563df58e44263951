// Quadratic tetrahedron (VTK/meshio "tetra10"; Gmsh's second-order tet, whose last two
// mid-nodes meshio swaps into this order). Corners 0..3 as Tet4, then one node in the middle of
// each edge: 4:(0,1) 5:(1,2) 6:(2,0) 7:(0,3) 8:(1,3) 9:(2,3).
// With the barycentric coordinates L = (1 - xi - eta - zeta, xi, eta, zeta):
//   corner a:      N_a = L_a (2 L_a - 1)
//   edge (a, b):   N   = 4 L_a L_b
// B is linear on a straight-sided element, so the four-point degree-2 rule integrates K
// exactly; the consistent mass (degree 4) uses a conical product rule exact to degree 5.
#pragma once

#include "corotate/elements/tet4.hpp"

namespace corotate {

struct Tet10 : ShapeFromEvaluate<Tet10, 10> {
  static constexpr const char* name = "tetra10";
  static constexpr const char* generator_name = "tet10";
  static constexpr ReferenceDomain domain = ReferenceDomain::simplex;
  static constexpr int dim = 3;  // a solid: reference coordinates span 3D
  static constexpr int order = 2;
  static constexpr int num_nodes = 10;
  static constexpr int num_corners = 4;
  static constexpr int num_stiffness_points = 4;  // points of stiffness_rule()
  static constexpr auto edges = Tet4::edges;      // node 4 + i sits on edge i
  static constexpr auto faces = Tet4::faces;
  static constexpr auto corner_mirror = Tet4::corner_mirror;

  static Vec3 node(int a) {
    if (a < num_corners) return Tet4::node(a);
    const auto& e = edges[a - num_corners];
    return 0.5 * (Tet4::node(e[0]) + Tet4::node(e[1]));
  }

  // Values and reference gradients together, from the barycentric coordinates and their
  // (constant) gradients dL_a/dxi, the rows of Tet4's shape gradient.
  static void evaluate(const Vec3& xi, ShapeValues* n, ShapeGradient* g) {
    const Eigen::Vector4d L = Tet4::shape(xi);
    const Tet4::ShapeGradient dL = Tet4::shape_gradient(xi);
    for (int a = 0; a < num_corners; ++a) {
      if (n) (*n)(a) = L(a) * (2 * L(a) - 1);
      if (g) g->row(a) = (4 * L(a) - 1) * dL.row(a);
    }
    for (int i = 0; i < 6; ++i) {
      const int a = edges[i][0], b = edges[i][1];
      if (n) (*n)(num_corners + i) = 4 * L(a) * L(b);
      if (g) g->row(num_corners + i) = 4 * (L(b) * dL.row(a) + L(a) * dL.row(b));
    }
  }
  static Vec3 centre() { return Vec3::Constant(0.25); }
  static const QuadratureRule& stiffness_rule() {
    static const auto r = tet_degree2_rule();
    return r;
  }
  static const QuadratureRule& mass_rule() {
    static const auto r = tet_collapsed_gauss(4);
    return r;
  }
};

}  // namespace corotate
