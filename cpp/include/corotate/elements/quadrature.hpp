// Quadrature rules on the reference tetrahedron and the reference cube [-1, 1]^3.
#pragma once

#include <vector>

#include "corotate/common.hpp"

namespace corotate {

struct QuadratureRule {
  std::vector<Vec3> points;     // reference coordinates
  std::vector<double> weights;  // sum to the reference volume
};

// Tensor-product Gauss-Legendre rule with n points per direction (n = 1 to 4),
// exact for polynomials of degree 2n-1 in each variable.
QuadratureRule gauss_cube(int n);

// Rules on the reference tet {xi, eta, zeta >= 0, xi + eta + zeta <= 1} (volume 1/6).
QuadratureRule tet_centroid_rule();   // degree 1, one point
QuadratureRule tet_degree2_rule();    // degree 2, four points
// The conical product rule (Stroud): n^3 points from n-point Gauss-Legendre rules on the unit
// cube mapped onto the tet by collapsing its faces; exact for total degree 2n - 3.
QuadratureRule tet_collapsed_gauss(int n);

}  // namespace corotate
