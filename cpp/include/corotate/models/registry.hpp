// The element types and hyperelastic laws the model factory builds models for: one list
// each, so a new element type is its file in elements/ plus one entry in SolidElements (or
// MembraneElements), and a new law is its file in materials/ plus one entry in
// HyperelasticLaws. Every model family is then built for it, and its name appears in the
// lists that Python reads (model_names, cell_type_names).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "corotate/elements/hex20.hpp"
#include "corotate/elements/hex8.hpp"
#include "corotate/elements/tet4.hpp"
#include "corotate/elements/tri3.hpp"
#include "corotate/fem/element_kernel.hpp"
#include "corotate/materials/fixed_corotated.hpp"
#include "corotate/materials/log_neo_hookean.hpp"
#include "corotate/materials/mooney_rivlin.hpp"
#include "corotate/materials/stable_neo_hookean.hpp"
#include "corotate/materials/stvk.hpp"
#include "corotate/models/force_model.hpp"

namespace corotate {

template <class... T>
struct TypeList {};
template <class T>
struct Tag {
  using type = T;
};

using SolidElements = TypeList<Tet4, Hex8, Hex20>;
using MembraneElements = TypeList<Tri3>;
using HyperelasticLaws = TypeList<StVK, StableNeoHookean, FixedCorotated, LogNeoHookean, MooneyRivlin>;
using MembraneLaws = TypeList<StVK>;

// Calls f(Tag<T>{}) for the T of the list whose T::name equals name; false if none does.
template <class... T, class F>
bool visit_by_name(TypeList<T...>, const std::string& name, F&& f) {
  return ((name == T::name ? (f(Tag<T>{}), true) : false) || ...);
}
template <class... T>
std::vector<std::string> names_of(TypeList<T...>) {
  return {T::name...};
}

// The builders of each model family (null when the family has no such cell type or law);
// make_model in model_factory.hpp is the public entry point.
std::unique_ptr<ForceModel> make_linear_model(const std::string& cell_type, const Nodes& rest,
                                              const Connectivity& cells, const RegionMaterials& materials,
                                              const ModelOptions& options);
std::unique_ptr<ForceModel> make_corotational_model(const std::string& cell_type, const Nodes& rest,
                                                    const Connectivity& cells, const RegionMaterials& materials,
                                                    const ModelOptions& options);
std::unique_ptr<ForceModel> make_hyperelastic_model(const std::string& law, const std::string& cell_type,
                                                    const Nodes& rest, const Connectivity& cells,
                                                    const RegionMaterials& materials, const ModelOptions& options);

}  // namespace corotate
