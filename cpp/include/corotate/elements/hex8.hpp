// Trilinear hexahedron (VTK "hexahedron" ordering) on the reference cube [-1, 1]^3:
// nodes 0..3 on the bottom face (zeta = -1) counter-clockwise from (-1, -1), 4..7 above them.
#pragma once

#include <array>

#include "corotate/elements/element_topology.hpp"
#include "corotate/elements/quadrature.hpp"

namespace corotate {

struct Hex8 {
  static constexpr const char* name = "hexahedron";
  static constexpr const char* generator_name = "hex8";
  static constexpr ReferenceDomain domain = ReferenceDomain::cube;
  static constexpr int dim = 3;  // a solid: reference coordinates span 3D
  static constexpr int order = 1;
  static constexpr int num_nodes = 8;
  static constexpr int num_corners = 8;
  static constexpr int num_stiffness_points = 8;  // points of stiffness_rule()
  // In VTK's hexahedron20 mid-node order: the bottom ring, the top ring, the vertical edges.
  static constexpr std::array<std::array<int, 2>, 12> edges = {
      {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};
  static constexpr std::array<std::array<int, 4>, 6> faces = {
      {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
  static constexpr std::array<int, 8> corner_mirror = {4, 5, 6, 7, 0, 1, 2, 3};  // bottom <-> top
  using ShapeValues = Eigen::Matrix<double, num_nodes, 1>;
  using ShapeGradient = Eigen::Matrix<double, num_nodes, 3>;

  static Vec3 node(int a) {
    static const double s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                   {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    return Vec3(s[a][0], s[a][1], s[a][2]);
  }
  // The node indices, in this ordering, of the cube (i, j, k) of a structured grid whose
  // node (i, j, k) is id(i, j, k): node a sits at the corner offset by node(a)'s signs.
  template <class Id>
  static std::array<int, num_nodes> grid_cube(const Id& id, int i, int j, int k) {
    std::array<int, num_nodes> nodes;
    for (int a = 0; a < num_nodes; ++a) {
      const Vec3 s = node(a);
      nodes[a] = id(i + (s.x() > 0), j + (s.y() > 0), k + (s.z() > 0));
    }
    return nodes;
  }
  static ShapeValues shape(const Vec3& xi) {
    ShapeValues n;
    for (int a = 0; a < num_nodes; ++a) {
      const Vec3 s = node(a);
      n(a) = 0.125 * (1 + s.x() * xi.x()) * (1 + s.y() * xi.y()) * (1 + s.z() * xi.z());
    }
    return n;
  }
  static ShapeGradient shape_gradient(const Vec3& xi) {
    ShapeGradient g;
    for (int a = 0; a < num_nodes; ++a) {
      const Vec3 s = node(a);
      const double fx = 1 + s.x() * xi.x(), fy = 1 + s.y() * xi.y(), fz = 1 + s.z() * xi.z();
      g.row(a) << 0.125 * s.x() * fy * fz, 0.125 * fx * s.y() * fz, 0.125 * fx * fy * s.z();
    }
    return g;
  }
  static Vec3 centre() { return Vec3::Zero(); }
  static const QuadratureRule& stiffness_rule() {
    static const auto r = gauss_cube(2);
    return r;
  }
  static const QuadratureRule& mass_rule() {
    static const auto r = gauss_cube(2);
    return r;
  }
};

}  // namespace corotate
