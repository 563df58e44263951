#include "corotate/elements/quadrature.hpp"

#include <cmath>

namespace corotate {

namespace {

// Gauss-Legendre points and weights on [-1, 1].
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
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
    case 4: {
      const double r = std::sqrt(6.0 / 5.0), s = std::sqrt(30.0);
      const double inner = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * r), outer = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * r);
      x = {-outer, -inner, inner, outer};
      w = {(18 - s) / 36, (18 + s) / 36, (18 + s) / 36, (18 - s) / 36};
      break;
    }
    default: throw InvalidInput("Gauss-Legendre rules are provided with 1 to 4 points per direction");
  }
}

}  // namespace

QuadratureRule gauss_cube(int n) {
  std::vector<double> x, w;
  gauss_legendre(n, x, w);
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

QuadratureRule tet_collapsed_gauss(int n) {
  // (u, v, w) in [0, 1]^3 -> xi = u, eta = v (1 - u), zeta = w (1 - u)(1 - v), with
  // Jacobian (1 - u)^2 (1 - v): a polynomial of total degree p becomes one of degree p + 2 in
  // u, p + 1 in v and p in w, which n Gauss points integrate exactly when p + 2 <= 2n - 1.
  std::vector<double> x, w;
  gauss_legendre(n, x, w);
  QuadratureRule rule;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double u = 0.5 * (x[i] + 1), v = 0.5 * (x[j] + 1), t = 0.5 * (x[k] + 1);
        rule.points.emplace_back(u, v * (1 - u), t * (1 - u) * (1 - v));
        rule.weights.push_back(0.125 * w[i] * w[j] * w[k] * (1 - u) * (1 - u) * (1 - v));
      }
  return rule;
}

}  // namespace corotate
