#include "corotate/fem/validate_mesh.hpp"

#include <sstream>
#include <vector>

namespace corotate {

void validate_mesh(const Nodes& rest, const Connectivity& cells, int nodes_per_cell, const char* cell_name) {
  std::ostringstream msg;
  if (rest.cols() == 0) throw InvalidInput("mesh has no nodes");
  if (cells.rows() == 0) throw InvalidInput("mesh has no cells");
  if (cells.cols() != nodes_per_cell) {
    msg << cell_name << " cells need " << nodes_per_cell << " nodes each, got " << cells.cols();
    throw InvalidInput(msg.str());
  }
  const Index bad = first_non_finite_node(rest);
  if (bad >= 0) {
    msg << "rest position of node " << bad << " is not finite (NaN or infinity)";
    throw InvalidInput(msg.str());
  }
  for (Index e = 0; e < cells.rows(); ++e)
    for (Index a = 0; a < cells.cols(); ++a)
      if (cells(e, a) < 0 || cells(e, a) >= rest.cols()) {
        msg << "cell " << e << " refers to node " << cells(e, a) << ", out of range [0, " << rest.cols() << ")";
        throw InvalidInput(msg.str());
      }
  // A node in no cell has neither mass nor stiffness: every solve would be singular.
  std::vector<char> used(rest.cols(), 0);
  for (Index k = 0; k < cells.size(); ++k) used[cells.data()[k]] = 1;
  for (Index i = 0; i < rest.cols(); ++i)
    if (!used[i]) {
      msg << "node " << i << " belongs to no cell, so it has no mass or stiffness; remove unused nodes "
          << "(corotate.read_mesh does so by default)";
      throw InvalidInput(msg.str());
    }
}

}  // namespace corotate
