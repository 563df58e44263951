#include "corotate/elements/quadrature.hpp"

#include <cmath>

namespace corotate {

QuadratureRule gauss_cube(int n) {
  std::vector<double> x, w;
  switch (n) {
    case 1:
      x = {0.0};
      w = {2.0};
      break;
    case 2:
      x = {-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)};
      w = {1.0, 1.0};
      break;
    case 3:
      x = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
      w = {5.0 / 9, 8.0 / 9, 5.0 / 9};
      break;
    default: throw InvalidInput("gauss_cube: only 1, 2 or 3 points per direction are provided");
  }
  QuadratureRule rule;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        rule.points.emplace_back(x[i], x[j], x[k]);
        rule.weights.push_back(w[i] * w[j] * w[k]);
      }
  return rule;
}

QuadratureRule tet_centroid_rule() { return {{Vec3::Constant(0.25)}, {1.0 / 6.0}}; }

QuadratureRule tet_degree2_rule() {
  // The symmetric four-point rule: one point near each vertex.
  const double a = (5 + 3 * std::sqrt(5.0)) / 20, b = (5 - std::sqrt(5.0)) / 20;
  QuadratureRule rule;
  rule.points = {Vec3(b, b, b), Vec3(a, b, b), Vec3(b, a, b), Vec3(b, b, a)};
  rule.weights.assign(4, 1.0 / 24.0);
  return rule;
}

}  // namespace corotate
