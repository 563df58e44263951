// Builds a force model by name for a mesh of one cell type, and lists the names (the one
// source of the choices Python offers).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "corotate/elements/element_list.hpp"  // cell_type_names
#include "corotate/fem/element_kernel.hpp"
#include "corotate/models/force_model.hpp"

namespace corotate {

// model: "linear", "corotational" (co-rotated linear FEM, the paper's model), or a
// hyperelastic law: "stvk" (St. Venant-Kirchhoff), "neohookean" (stable Neo-Hookean),
// "fixed_corotated" (Stomakhin's fixed co-rotated law), "neohookean_log", "mooney_rivlin"; cell_type: a
// registered solid (every model) or membrane ("stvk" only) cell type (elements/element_list.hpp,
// VTK/meshio names). rest: 3 x n; cells: m x k node indices; materials: a Material, or one per
// region with each cell's region (region_materials.hpp). Throws InvalidInput naming what is wrong.
std::unique_ptr<ForceModel> make_model(const std::string& model, const std::string& cell_type, const Nodes& rest,
                                       const Connectivity& cells, const RegionMaterials& materials,
                                       const ModelOptions& options = ModelOptions());

std::vector<std::string> model_names();      // every model name make_model accepts
// The models available for a cell type (empty for an unknown one).
std::vector<std::string> models_for_cell_type(const std::string& cell_type);

// Throws InvalidInput saying what a renamed model (or law) is called now, when name is one
// of the old names (e.g. "corotated", now "fixed_corotated"); does nothing otherwise.
// make_model and the constitutive_law binding call it before "unknown model".
void check_renamed_model(const std::string& name);

}  // namespace corotate
