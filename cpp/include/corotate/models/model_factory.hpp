// Builds a force model by name for a mesh of one cell type.
#pragma once

#include <memory>
#include <string>

#include "corotate/material.hpp"
#include "corotate/models/force_model.hpp"

namespace corotate {

// Settings that only some models use.
struct ModelOptions {
  double thickness = 1.0;    // sheet thickness [m] of "triangle" cells (membranes); ignored for solids
  bool project_psd = false;  // hyperelastic models: project each element stiffness to PSD (implicit solves)
};

// model: "linear", "corotational" (co-rotated linear FEM), or the hyperelastic models "stvk"
// (St. Venant-Kirchhoff), "neohookean" (stable Neo-Hookean) and "corotated" (fixed
// co-rotated); cell_type: "tetra", "hexahedron", "hexahedron20" (all models) or "triangle"
// (membrane sheets, "stvk" only) (VTK/meshio names). rest: 3 x n; cells: m x k node indices.
std::unique_ptr<ForceModel> make_model(const std::string& model, const std::string& cell_type, const Nodes& rest,
                                       const Connectivity& cells, const Material& material,
                                       const ModelOptions& options = ModelOptions());

}  // namespace corotate
