// Quadrature rules on the reference tetrahedron and the reference cube [-1, 1]^3.
#pragma once

#include <vector>

#include "corotate/common.hpp"

namespace corotate {

struct QuadratureRule {
  std::vector<Vec3> points;     // reference coordinates
  std::vector<double> weights;  // sum to the reference volume
};

// Tensor-product Gauss-Legendre rule with n points per direction (n = 1, 2 or 3),
// exact for polynomials of degree 2n-1 in each variable.
QuadratureRule gauss_cube(int n);

// Rules on the reference tet {xi, eta, zeta >= 0, xi + eta + zeta <= 1} (volume 1/6).
QuadratureRule tet_centroid_rule();   // degree 1, one point
QuadratureRule tet_degree2_rule();    // degree 2, four points

}  // namespace corotate
