// Isotropic linear-elastic material (E, nu, rho) and its 6x6 constitutive matrix.
#pragma once

#include "corotate/common.hpp"

namespace corotate {

struct Material {
  double youngs_modulus = 1e6;  // E  [Pa], > 0
  double poisson_ratio = 0.3;   // nu [-], in (-1, 0.5)
  double density = 1000.0;      // rho [kg/m^3], > 0

  // Largest ratio of the two moduli, lambda / mu (nu -> 0.5) or mu / K (nu -> -1), that
  // validate() accepts. Beyond it the element stiffness mixes entries 1e6 apart: in double
  // precision the weaker mode keeps fewer than 10 of 16 digits after assembly, the PCG
  // tolerances (relative 1e-2 by default) no longer resolve it, and linear tets lock. A ratio
  // of 1e6 means nu up to 0.4999995 (lambda/mu = 2 nu / (1 - 2 nu)) and down to -0.9999955.
  static constexpr double max_modulus_ratio = 1e6;

  // Throws InvalidInput naming the offending parameter: non-finite or out-of-range values,
  // moduli further apart than max_modulus_ratio, and an E so large that lambda, mu or E^2
  // (stiffness products, energies) overflow.
  void validate() const;

  double lame_lambda() const;
  double lame_mu() const;

  // H in Voigt order (xx, yy, zz, yz, xz, xy) with engineering shear strains,
  // so that stress = H * B * u and K_e = integral of B^T H B.
  Eigen::Matrix<double, 6, 6> elasticity_matrix() const;
};

}  // namespace corotate
