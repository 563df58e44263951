// Materials given in a law's own parameters: the lookup of the law among the registered ones
// (registry.hpp) and the checks of its parameters (law_parameters.hpp).
#include "corotate/materials/law_parameters.hpp"

#include <cmath>
#include <tuple>

#include "corotate/models/registry.hpp"

namespace corotate {

namespace {

// Calls f(Tag<Law>{}) for the registered law with parameters of its own named law; false if
// there is none.
template <class F>
bool visit_parametrised_law(const std::string& law, F&& f) {
  bool found = false;
  visit_by_name(HyperelasticLaws{}, law, [&](auto tag) {
    using L = typename decltype(tag)::type;
    if constexpr (law_has_parameters<L>) {
      f(tag);
      found = true;
    }
  });
  return found;
}

std::string parametrised_law_list() {
  std::string out;
  for (const LawDeclaration& d : law_declarations()) {
    out += (out.empty() ? "'" : ", '") + d.law + "' (";
    for (size_t i = 0; i < d.parameters.size(); ++i) out += (i ? ", " : "") + d.parameters[i].first;
    out += ")";
  }
  return out;
}

[[noreturn]] void unknown_law(const std::string& law) {
  throw InvalidInput("no law '" + law + "' with parameters of its own (choose " + parametrised_law_list() +
                     "; the other laws take E and nu)");
}

template <class L>
std::pair<double, double> checked_moduli(const std::vector<double>& values) {
  for (int i = 0; i < num_law_parameters<L>(); ++i) L::parameters[i].check(L::name, values[i]);
  return L::small_strain_moduli(values.data());
}

// E and nu from the Lame parameters.
std::pair<double, double> youngs_and_poisson(double lambda, double mu) {
  return {mu * (3 * lambda + 2 * mu) / (lambda + mu), lambda / (2 * (lambda + mu))};
}

}  // namespace

std::vector<LawDeclaration> law_declarations() {
  std::vector<LawDeclaration> out;
  for (const std::string& name : names_of(HyperelasticLaws{}))
    visit_parametrised_law(name, [&](auto tag) {
      using L = typename decltype(tag)::type;
      LawDeclaration d{L::name, {}};
      for (const LawParameter& p : L::parameters) d.parameters.emplace_back(p.name, p.meaning);
      out.push_back(d);
    });
  return out;
}

Material material_of_law(const std::string& law, const std::vector<std::pair<std::string, double>>& named,
                         double density) {
  Material m;
  m.law = law;
  m.density = density;
  const bool found = visit_parametrised_law(law, [&](auto tag) {
    using L = typename decltype(tag)::type;
    std::vector<bool> given(num_law_parameters<L>(), false);
    m.parameters.assign(num_law_parameters<L>(), 0.0);
    std::string names;
    for (const LawParameter& p : L::parameters) names += (names.empty() ? "" : ", ") + std::string(p.name);
    for (const auto& [name, value] : named) {
      int i = 0;
      while (i < num_law_parameters<L>() && name != L::parameters[i].name) ++i;
      if (i == num_law_parameters<L>())
        throw InvalidInput("'" + law + "' has no parameter '" + name + "' (its parameters: " + names + ")");
      if (given[i]) throw InvalidInput("'" + law + "' parameter " + name + " is given twice");
      given[i] = true;
      m.parameters[i] = value;
    }
    for (int i = 0; i < num_law_parameters<L>(); ++i)
      if (!given[i])
        throw InvalidInput("'" + law + "' parameter " + L::parameters[i].name + " (" + L::parameters[i].meaning +
                           ") is missing (its parameters: " + names + ")");
    const auto [lambda, mu] = checked_moduli<L>(m.parameters);
    std::tie(m.youngs_modulus, m.poisson_ratio) = youngs_and_poisson(lambda, mu);
  });
  if (!found) unknown_law(law);
  m.validate();
  return m;
}

void detail::check_law_material(const Material& m) {
  const bool found = visit_parametrised_law(m.law, [&](auto tag) {
    using L = typename decltype(tag)::type;
    if (static_cast<int>(m.parameters.size()) != num_law_parameters<L>())
      throw InvalidInput("'" + m.law + "' takes " + std::to_string(num_law_parameters<L>()) + " parameters, got " +
                         std::to_string(m.parameters.size()));
    const auto [lambda, mu] = checked_moduli<L>(m.parameters);
    const auto [E, nu] = youngs_and_poisson(lambda, mu);
    if (E != m.youngs_modulus || nu != m.poisson_ratio)
      throw InvalidInput("a '" + m.law +
                         "' material's E and nu must be its small-strain moduli (make it with "
                         "material_of_law)");
  });
  if (!found) unknown_law(m.law);
}

}  // namespace corotate
