// Builds a force model by name for a mesh of one cell type.
#pragma once

#include <memory>
#include <string>

#include "corotate/material.hpp"
#include "corotate/models/force_model.hpp"

namespace corotate {

// model: "linear" or "corotational"; cell_type: "tetra", "hexahedron" or "hexahedron20"
// (VTK/meshio names). rest: 3 x n; cells: m x k node indices.
std::unique_ptr<ForceModel> make_model(const std::string& model, const std::string& cell_type, const Nodes& rest,
                                       const Connectivity& cells, const Material& material);

}  // namespace corotate
