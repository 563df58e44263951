// The two products of a modal basis Phi (3n x r, row-major, DOF = 3*node + axis) that run
// every frame: recovering nodal displacements u = Phi q (all nodes or a subset) and
// projecting nodal forces onto the basis p = Phi^T f (only the loaded nodes' rows are read).
// Both write into buffers the caller owns and allocate nothing.
#pragma once

#include "corotate/common.hpp"

namespace corotate {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using BasisMap = Eigen::Map<const RowMatrix>;
// q by reference: a NumPy view of the state is read in place, without a copy.
using VecRef = Eigen::Ref<const Vec>;

// Throws InvalidInput naming the first node index outside [0, n_nodes).
void check_node_indices(const long long* nodes, Index count, Index n_nodes);

// out (3 x count, i.e. (count, 3) row-major) = displacements of the given nodes; nodes ==
// nullptr means all nodes (count = n).
void recover_displacements(const BasisMap& basis, const VecRef& q, const long long* nodes, Index count, double* out);

// The same from a single-precision copy of the basis (rows x r, row-major): half the memory
// traffic of the full recovery, which is bandwidth-bound; float products and sums (r <= 64).
void recover_displacements(const float* basis, Index rows, Index r, const VecRef& q, const long long* nodes,
                           Index count, double* out);

// p = sum over the given nodes of Phi[rows of node]^T forces[node] (forces: (count, 3)).
// p: r entries, overwritten.
void project_nodal_forces(const BasisMap& basis, const long long* nodes, Index count, const double* forces, double* p);

}  // namespace corotate
