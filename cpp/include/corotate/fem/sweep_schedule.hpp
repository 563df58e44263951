// The order in which an element sweep visits its chunks, and which of them run concurrently.
//
// Elements are taken in chunks of consecutive elements. Two chunks that share a node add into
// the same global blocks, so they must not run at the same time, and the order in which they
// add must not depend on the thread count (threaded and one-thread runs then agree to the
// bit). A colouring of the chunks satisfies both, but it sweeps colour by colour: each
// colour's chunks lie all over the mesh, so every matrix row shared by chunks of two colours
// is fetched from memory twice. At 122,880 tets (a 15 MB matrix, far beyond L2) that cost a
// sixth of the one-thread sweep.
//
// This schedule is a nested dissection of the chunk sequence instead. The chunks are split in
// the middle; those of the second half that share a node with the first form the separator
// and wait; the two halves (now sharing no node) are split again in the same way, down to a
// fixed depth. The sweep runs all the leaves (concurrently), then the separators of the
// deepest splits, ..., then the first split's separator. The order is fixed by the mesh
// alone, and on one thread it is the natural order of each leaf, with only the separators'
// few chunks out of place.
#pragma once

#include <vector>

#include "corotate/common.hpp"

namespace corotate {

struct SweepSchedule {
  // phases[p][q]: the chunks of part q of phase p, in the order they run. Phases run in
  // order; the parts of one phase share no node and may run concurrently.
  std::vector<std::vector<std::vector<int>>> phases;
  Index num_chunks = 0;
};

// cells: nodes_per_element node indices per element (row-major), num_elements of them, nodes
// in [0, num_nodes). depth: splits from the top (2^depth leaves at most); a part of fewer
// than min_leaf_chunks chunks is not split.
SweepSchedule schedule_sweep(const int* cells, int nodes_per_element, Index num_elements, Index num_nodes,
                             Index chunk_size, int depth = 3, Index min_leaf_chunks = 4);

}  // namespace corotate
