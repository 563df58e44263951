// The stiff blocks a step adds to its system's diagonal (contact springs), for the solvers.
#pragma once

#include <vector>

#include "corotate/common.hpp"

namespace corotate {

// Blocks a step added to its system's diagonal on top of the body's own (stiff contact
// springs, node by node; a node may appear more than once). They are in A already; an
// iterative solver whose coarse level was built from an earlier system (two_level) adds
// them to it, since its coarse correction would otherwise push against them.
struct DiagonalTerms {
  std::vector<Index> nodes;
  std::vector<Mat3> blocks;  // scaled as they went into A
  void clear() {
    nodes.clear();
    blocks.clear();
  }
  bool empty() const { return nodes.empty(); }
};

}  // namespace corotate
