// The structured mesh of an axis-aligned box, for every registered solid element: the one
// generator behind corotate.box / corotate.beam, the C++ benchmark's beam and the C++ tests,
// so all of them see the same mesh node for node.
//
// The box [origin, origin + size] is cut into nx x ny x nz cuboids. Cube elements (Hex8, Hex20)
// take one cell per cuboid. Simplices (Tet4, Tet10) cut each cuboid into the 6 Kuhn tets that
// share one of its diagonals, mirrored from cuboid to cuboid along each axis, so that the mesh
// is conforming and symmetric about every plane between cuboid pairs: a beam with an even
// number of cells across then bends in its plane of load (one diagonal direction everywhere
// would twist it sideways, by 10 % of the deflection on a 4 x 4 cross-section).
// Quadratic elements add a node in the middle of every cell edge, shared between the cells.
// Nodes are numbered x-major with z fastest on the grid of half steps (quadratic) or steps
// (linear), so a slab of constant x holds consecutive indices.
#pragma once

#include <array>
#include <string>

#include "corotate/common.hpp"

namespace corotate {

struct StructuredMesh {
  Nodes points;        // 3 x n
  Connectivity cells;  // m x num_nodes, VTK node order, positively oriented
  std::string cell_type;
};

// element: a solid's generator name ("tet4", "tet10", "hex8", "hex20"; see cell_types());
// cells: cuboids per axis (>= 1); size: edge lengths (> 0, finite); origin: the minimum corner.
// Throws InvalidInput naming the bad argument.
StructuredMesh structured_box(const std::string& element, const std::array<int, 3>& cells, const Vec3& size,
                              const Vec3& origin = Vec3::Zero());

}  // namespace corotate
