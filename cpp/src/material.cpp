#include "corotate/material.hpp"

#include <cmath>
#include <sstream>

namespace corotate {

void Material::validate() const {
  if (!std::isfinite(density) || density <= 0) {
    std::ostringstream msg;
    msg << "density must be positive and finite, got rho = " << density;
    throw InvalidInput(msg.str());
  }
  if (!law.empty()) detail::check_law_material(*this);
  // For a law's material E and nu are derived: say so where they are the problem.
  const std::string context = law.empty() ? "" : "the small-strain moduli of this '" + law + "' material: ";
  auto fail = [&](const std::string& what) { throw InvalidInput(context + what); };
  std::ostringstream msg;
  if (!std::isfinite(youngs_modulus) || youngs_modulus <= 0) {
    msg << "Young's modulus must be positive and finite, got E = " << youngs_modulus;
    fail(msg.str());
  }
  if (!std::isfinite(poisson_ratio) || poisson_ratio >= 0.5 || poisson_ratio <= -1.0) {
    msg << "Poisson ratio must lie in (-1, 0.5), got nu = " << poisson_ratio;
    if (poisson_ratio >= 0.5)
      msg << " (nu >= 0.5 makes the material incompressible, which this compressible model cannot represent)";
    fail(msg.str());
  }
  const double lambda = lame_lambda(), mu = lame_mu();
  if (!std::isfinite(lambda) || !std::isfinite(mu) || !std::isfinite(youngs_modulus * youngs_modulus)) {
    msg << "Young's modulus E = " << youngs_modulus << " (nu = " << poisson_ratio
        << ") is too large: the Lame parameters or products of stiffnesses (E^2) overflow a double; "
           "give E in Pa (realistic values are below 1e13)";
    fail(msg.str());
  }
  const double bulk = youngs_modulus / (3 * (1 - 2 * poisson_ratio));
  if (lambda / mu > max_modulus_ratio || mu / bulk > max_modulus_ratio) {
    msg.precision(17);
    msg << "Poisson ratio nu = " << poisson_ratio << " is too close to "
        << (poisson_ratio > 0 ? "0.5: lambda/mu = " : "-1: mu/K = ") << (poisson_ratio > 0 ? lambda / mu : mu / bulk)
        << " exceeds " << max_modulus_ratio
        << ", which makes the stiffness too ill-conditioned to solve (nu must lie in [-0.9999955, 0.4999995])";
    fail(msg.str());
  }
}

double Material::lame_lambda() const {
  return youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
}

double Material::lame_mu() const { return youngs_modulus / (2 * (1 + poisson_ratio)); }

Eigen::Matrix<double, 6, 6> Material::elasticity_matrix() const {
  const double lambda = lame_lambda(), mu = lame_mu();
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  H.topLeftCorner<3, 3>().setConstant(lambda);
  H.topLeftCorner<3, 3>().diagonal().array() += 2 * mu;
  H.bottomRightCorner<3, 3>().diagonal().setConstant(mu);
  return H;
}

}  // namespace corotate
