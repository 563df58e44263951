// Quadratic serendipity hexahedron (VTK "hexahedron20" ordering) on [-1, 1]^3:
// corners 0..7 as Hex8, then mid-edge nodes 8:(0,1) 9:(1,2) 10:(2,3) 11:(3,0)
// 12:(4,5) 13:(5,6) 14:(6,7) 15:(7,4) 16:(0,4) 17:(1,5) 18:(2,6) 19:(3,7).
#pragma once

#include "corotate/elements/hex8.hpp"

namespace corotate {

struct Hex20 : ShapeFromEvaluate<Hex20, 20> {
  static constexpr const char* name = "hexahedron20";
  static constexpr const char* generator_name = "hex20";
  static constexpr ReferenceDomain domain = ReferenceDomain::cube;
  static constexpr int dim = 3;  // a solid: reference coordinates span 3D
  static constexpr int order = 2;
  static constexpr int num_nodes = 20;
  static constexpr int num_corners = 8;
  static constexpr int num_stiffness_points = 27;  // points of stiffness_rule()
  static constexpr auto edges = Hex8::edges;  // node 8 + i sits on edge i
  static constexpr auto faces = Hex8::faces;
  static constexpr auto corner_mirror = Hex8::corner_mirror;

  static Vec3 node(int a) {
    static const double s[20][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1},
                                    {1, -1, 1},   {1, 1, 1},   {-1, 1, 1}, {0, -1, -1}, {1, 0, -1},
                                    {0, 1, -1},   {-1, 0, -1}, {0, -1, 1}, {1, 0, 1},   {0, 1, 1},
                                    {-1, 0, 1},   {-1, -1, 0}, {1, -1, 0}, {1, 1, 0},   {-1, 1, 0}};
    return Vec3(s[a][0], s[a][1], s[a][2]);
  }

  // Values and reference gradients together: the formulas share their factors.
  static void evaluate(const Vec3& xi, ShapeValues* n, ShapeGradient* g) {
    for (int a = 0; a < num_nodes; ++a) {
      const Vec3 s = node(a);
      const Vec3 f = Vec3::Ones() + s.cwiseProduct(xi);  // (1 + s_i xi_i) per direction
      double value;
      Vec3 grad;
      if (a < 8) {  // corner: 1/8 prod(1 + s_i xi_i) * (s.xi - 2)
        const double c = s.dot(xi) - 2;
        const double p = f.prod();
        value = 0.125 * p * c;
        for (int i = 0; i < 3; ++i) {
          const double dp = s(i) * f((i + 1) % 3) * f((i + 2) % 3);
          grad(i) = 0.125 * (dp * c + p * s(i));
        }
      } else {  // mid-edge: the coordinate with s_i = 0 carries (1 - xi_i^2)
        int i0 = 0;
        while (s(i0) != 0) ++i0;
        const int i1 = (i0 + 1) % 3, i2 = (i0 + 2) % 3;
        const double q = 1 - xi(i0) * xi(i0);
        value = 0.25 * q * f(i1) * f(i2);
        grad(i0) = 0.25 * (-2 * xi(i0)) * f(i1) * f(i2);
        grad(i1) = 0.25 * q * s(i1) * f(i2);
        grad(i2) = 0.25 * q * f(i1) * s(i2);
      }
      if (n) (*n)(a) = value;
      if (g) g->row(a) = grad.transpose();
    }
  }
  static Vec3 centre() { return Vec3::Zero(); }
  static const QuadratureRule& stiffness_rule() {
    static const auto r = gauss_cube(3);
    return r;
  }
  static const QuadratureRule& mass_rule() {
    static const auto r = gauss_cube(3);
    return r;
  }
};

}  // namespace corotate
