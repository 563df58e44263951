// An isotropic elastic material: its small-strain moduli (E, nu), its density and, when it
// is given in a hyperelastic law's own parameters (Mooney-Rivlin's C10, C01, bulk), that law
// and those parameters; and its 6x6 small-strain constitutive matrix.
//
// E and nu are the common case: every model takes them (the hyperelastic laws written in the
// Lame parameters directly, a law with its own parameters derives them from E and nu, see
// law_parameters.hpp). A material given in a law's parameters is made by material_of_law,
// which sets E and nu to the law's small-strain moduli: the linear and co-rotational models
// (and the stiffness a modal reduction or force feedback starts from) then use exactly the
// law's stiffness at rest, and only that law's own model takes the material beyond it.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

struct Material {
  double youngs_modulus = 1e6;  // E  [Pa], > 0 (small-strain)
  double poisson_ratio = 0.3;   // nu [-], in (-1, 0.5) (small-strain)
  double density = 1000.0;      // rho [kg/m^3], > 0
  std::string law{};               // empty: given by E and nu; else the law whose parameters follow
  std::vector<double> parameters{};  // that law's parameters, in the order it declares them

  // Largest ratio of the two moduli, lambda / mu (nu -> 0.5) or mu / K (nu -> -1), that
  // validate() accepts. Beyond it the element stiffness mixes entries 1e6 apart: in double
  // precision the weaker mode keeps fewer than 10 of 16 digits after assembly, the PCG
  // tolerances (relative 1e-2 by default) no longer resolve it, and linear tets lock. A ratio
  // of 1e6 means nu up to 0.4999995 (lambda/mu = 2 nu / (1 - 2 nu)) and down to -0.9999955.
  static constexpr double max_modulus_ratio = 1e6;

  // Throws InvalidInput naming the offending parameter: non-finite or out-of-range values,
  // moduli further apart than max_modulus_ratio, and an E so large that lambda, mu or E^2
  // (stiffness products, energies) overflow; for a law's material also its parameters (each
  // checked as the law declares) and E, nu that are not the law's small-strain moduli.
  void validate() const;

  // The same material given by E and nu alone (its small-strain moduli), for models that
  // linearise at rest whatever the law (the averaged force feedback).
  Material small_strain() const { return {youngs_modulus, poisson_ratio, density, {}, {}}; }

  double lame_lambda() const;
  double lame_mu() const;

  // H in Voigt order (xx, yy, zz, yz, xz, xy) with engineering shear strains,
  // so that stress = H * B * u and K_e = integral of B^T H B.
  Eigen::Matrix<double, 6, 6> elasticity_matrix() const;
};

// A material given in the parameters of a law (a HyperelasticLaws entry that declares its
// own): named values in any order, checked against what the law declares (an unknown or
// missing name, a value out of its range: InvalidInput naming it), with E and nu set to the
// law's small-strain moduli. Defined with the law list (src/models/law_parameters.cpp).
Material material_of_law(const std::string& law, const std::vector<std::pair<std::string, double>>& named,
                         double density);

// What a law declares about its parameters, for the laws that have their own (the one list
// Python reads): the law's name and, per parameter, its name and meaning.
struct LawDeclaration {
  std::string law;
  std::vector<std::pair<std::string, std::string>> parameters;  // (name, meaning with unit)
};
std::vector<LawDeclaration> law_declarations();

namespace detail {
// Material::validate's part for a law's material (defined with the law list): the law is
// known, its parameters pass their checks, and E, nu are its small-strain moduli.
void check_law_material(const Material& m);
}  // namespace detail

}  // namespace corotate
