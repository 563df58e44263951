// Linear triangle (VTK "triangle") as a membrane: a flat element of a sheet in 3D space,
// or of a 2D body in the z = 0 plane (plane stress is the same element with in-plane loads).
//
// Its reference configuration is its own rest plane: with d1 = X1 - X0, d2 = X2 - X0 and the
// orthonormal in-plane frame e1 = d1/|d1|, e2 = n x e1 (n the unit normal),
//     Dm = [e1.d1  e1.d2; e2.d1  e2.d2]   (2 x 2, upper triangular, det Dm = 2 area),
// and for positions x the 3 x 2 deformation gradient is F = Ds Dm^-1, Ds = [x1 - x0, x2 - x0]
// (Sifakis & Barbic 2012; the explainer uses node 3 as the origin, which is equivalent).
// Written as F = x_e G with G = [-1 -1; 1 0; 0 1] Dm^-1 (3 x 2, row a = dN_a/dX in the plane).
#pragma once

#include <sstream>

#include "corotate/elements/element_topology.hpp"

namespace corotate {

struct Tri3 {
  static constexpr const char* name = "triangle";
  static constexpr const char* generator_name = "tri3";
  static constexpr ReferenceDomain domain = ReferenceDomain::simplex;
  static constexpr int dim = 2;  // a membrane: reference coordinates span its rest plane
  static constexpr int order = 1;
  static constexpr int num_nodes = 3;
  static constexpr int num_corners = 3;
  static constexpr int num_stiffness_points = 1;  // F is constant on the element
  static constexpr std::array<std::array<int, 2>, 3> edges = {{{0, 1}, {1, 2}, {2, 0}}};
  static constexpr std::array<std::array<int, 3>, 0> faces = {};  // a sheet is its own surface
  static constexpr std::array<int, 3> corner_mirror = {0, 2, 1};
  // Reference coordinates of the nodes in the unit triangle (third entry unused).
  static Vec3 node(int a) { return a == 0 ? Vec3::Zero() : Vec3(Vec3::Unit(a - 1)); }
  using NodeMatrix = Eigen::Matrix<double, 3, 3>;
  using Gradient = Eigen::Matrix<double, 3, 2>;

  struct Rest {
    Gradient G;
    double area;
  };

  // Rest frame of an element; a triangle without clear area is rejected by index.
  static Rest rest(const NodeMatrix& X, Index element) {
    const Vec3 d1 = X.col(1) - X.col(0), d2 = X.col(2) - X.col(0);
    const Vec3 n = d1.cross(d2);
    const double extent = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).maxCoeff();
    if (!(n.norm() > 1e-10 * extent * extent)) {
      std::ostringstream msg;
      msg << "element " << element << " (" << name
          << ") has zero area (degenerate: its nodes are coincident or collinear)";
      throw InvalidInput(msg.str());
    }
    const Vec3 e1 = d1.normalized(), e2 = n.normalized().cross(e1);
    Eigen::Matrix2d Dm;
    Dm << e1.dot(d1), e1.dot(d2), e2.dot(d1), e2.dot(d2);
    Gradient Z;
    Z << -1, -1, 1, 0, 0, 1;
    return {Z * Dm.inverse(), 0.5 * n.norm()};
  }

  // Consistent mass of a linear triangle of mass m: m/12 (1 + delta_ab); lumped: m/3 each.
  static Eigen::Matrix3d consistent_mass(double m) {
    return (m / 12) * (Eigen::Matrix3d::Ones() + Eigen::Matrix3d::Identity());
  }
  static Vec3 lumped_mass(double m) { return Vec3::Constant(m / 3); }
};

}  // namespace corotate
