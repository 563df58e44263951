// How a constitutive law states its parameters, and how a law object is made from a Material.
//
// Two kinds of law:
//  * Laws written in the Lame parameters (StVK, the Neo-Hookeans, fixed co-rotated) are an
//    aggregate {lambda, mu} and take both from the material's E and nu.
//  * A law with parameters of its own declares them, each with the values it admits:
//        static constexpr LawParameter parameters[] = {positive("C10", "..."), ...};
//        static Law from_parameters(const double* values);       in that order, checked
//        static std::vector<double> parameters_from_moduli(double lambda, double mu);
//                                                                 from E and nu (the law's
//                                                                 member with those moduli)
//        static std::pair<double, double> small_strain_moduli(const double* values);
//                                                                 (lambda, mu) at rest
//    It then takes a material given in its parameters (material_of_law) as it is, and a
//    material given by E and nu through parameters_from_moduli. A material given in another
//    law's parameters is refused: converting between nonlinear laws would be a guess.
// The name lists Python offers are read from these declarations (law_declarations).
#pragma once

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

#include "corotate/material.hpp"

namespace corotate {

// A named parameter and the interval of values it admits (always finite as well).
struct LawParameter {
  const char* name;     // as the user spells it: "C10"
  const char* meaning;  // what it is, with its unit: "... [Pa]"
  double lower = 0.0;
  bool lower_included = false;
  double upper = std::numeric_limits<double>::infinity();

  // Throws InvalidInput naming the law, the parameter and the admitted values.
  void check(const std::string& law, double value) const {
    const bool above = lower_included ? value >= lower : value > lower;
    if (std::isfinite(value) && above && value < upper) return;
    std::ostringstream msg;
    msg << law << " parameter " << name << " (" << meaning << ") must be finite and " << (lower_included ? ">= " : "> ")
        << lower;
    if (std::isfinite(upper)) msg << " and < " << upper;
    msg << ", got " << value;
    throw InvalidInput(msg.str());
  }
};

constexpr LawParameter positive(const char* name, const char* meaning) { return {name, meaning, 0.0, false}; }
constexpr LawParameter non_negative(const char* name, const char* meaning) { return {name, meaning, 0.0, true}; }

// Whether Law declares parameters of its own.
template <class Law, class = void>
struct LawHasParameters : std::false_type {};
template <class Law>
struct LawHasParameters<Law, std::void_t<decltype(Law::parameters)>> : std::true_type {};
template <class Law>
inline constexpr bool law_has_parameters = LawHasParameters<Law>::value;

template <class Law>
constexpr int num_law_parameters() {
  return static_cast<int>(std::extent_v<decltype(Law::parameters)>);
}

// The law object for a material: the material's own parameters when it is given in Law's,
// else from its E and nu. plane_stress: for a membrane (lambda becomes the plane-stress
// 2 lambda mu / (lambda + 2 mu) of a sheet free through its thickness). Throws InvalidInput
// for a material given in another law's parameters. The material is validated already.
template <class Law>
Law law_of_material(const Material& m, bool plane_stress = false) {
  if (!m.law.empty() && m.law != Law::name) {
    throw InvalidInput(
        "the '" + std::string(Law::name) + "' model needs a material given by E and nu" +
        (law_has_parameters<Law> ? std::string(" or by '") + Law::name + "' parameters" : std::string()) +
        "; this one is given by '" + m.law + "' parameters (simulate it with model='" + m.law +
        "', or with 'linear' or 'corotational', which use its small-strain moduli)");
  }
  const double lambda = m.lame_lambda(), mu = m.lame_mu();
  const double lambda_used = plane_stress ? 2 * lambda * mu / (lambda + 2 * mu) : lambda;
  if constexpr (law_has_parameters<Law>) {
    if (m.law.empty()) return Law::from_parameters(Law::parameters_from_moduli(lambda_used, mu).data());
    return Law::from_parameters(m.parameters.data());
  } else {
    return Law{lambda_used, mu};
  }
}

}  // namespace corotate
