// Isotropic linear-elastic material (E, nu, rho) and its 6x6 constitutive matrix.
#pragma once

#include "corotate/common.hpp"

namespace corotate {

struct Material {
  double youngs_modulus = 1e6;  // E  [Pa], > 0
  double poisson_ratio = 0.3;   // nu [-], in (-1, 0.5)
  double density = 1000.0;      // rho [kg/m^3], > 0

  // Throws InvalidInput naming the offending parameter.
  void validate() const;

  double lame_lambda() const;
  double lame_mu() const;

  // H in Voigt order (xx, yy, zz, yz, xz, xy) with engineering shear strains,
  // so that stress = H * B * u and K_e = integral of B^T H B.
  Eigen::Matrix<double, 6, 6> elasticity_matrix() const;
};

}  // namespace corotate
