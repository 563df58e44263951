// The hyperelastic laws the model factory builds models for (the element types are listed in
// elements/element_list.hpp): a new law is its file in materials/ plus one entry in
// HyperelasticLaws. Every model family is then built for it on every element, and its name
// appears in the lists that Python reads (model_names).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "corotate/elements/element_list.hpp"
#include "corotate/fem/element_kernel.hpp"
#include "corotate/materials/fixed_corotated.hpp"
#include "corotate/materials/log_neo_hookean.hpp"
#include "corotate/materials/mooney_rivlin.hpp"
#include "corotate/materials/stable_neo_hookean.hpp"
#include "corotate/materials/stvk.hpp"
#include "corotate/models/force_model.hpp"

namespace corotate {

using HyperelasticLaws = TypeList<StVK, StableNeoHookean, FixedCorotated, LogNeoHookean, MooneyRivlin>;
using MembraneLaws = TypeList<StVK>;

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
