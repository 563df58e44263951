// Checks what any mesh-based model needs before it precomputes anything.
#pragma once

#include "corotate/common.hpp"

namespace corotate {

// Finite rest positions, at least one node and cell, nodes_per_cell nodes per cell, in-range
// indices, and no node outside every cell (it would have neither mass nor stiffness).
// Throws InvalidInput naming the node or cell.
void validate_mesh(const Nodes& rest, const Connectivity& cells, int nodes_per_cell, const char* cell_name);

}  // namespace corotate
