// The cell-type table: the facts of every registered element (element_topology.hpp) in one
// runtime list, bound to Python as corotate._core.cell_types() and read there by the Mesh
// (node counts, faces, mirror maps, generator names), the choices and the tests; and the
// geometric questions about cells that are answered by the element itself.
#pragma once

#include <string>
#include <vector>

#include "corotate/elements/element_topology.hpp"

namespace corotate {

// Every registered cell type, solids first (element_list.hpp).
std::vector<CellTypeFacts> cell_types();

// The signed volume of every cell (m,): the integral of det(dX/dxi) by the element's mass
// rule, exact for straight-sided and curved cells of polynomial map (positive in the element's
// orientation, negative for a mirrored cell); for membranes the (unsigned) areas.
// rest: 3 x n node coordinates; cells: m x num_nodes. Node indices are checked.
Vec signed_cell_volumes(const std::string& cell_type, const Nodes& rest, const Connectivity& cells);

}  // namespace corotate
