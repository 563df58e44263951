// The two-level preconditioner's coarse level, built in node x aggregate blocks: the smoothed
// prolongator P = T - w D^-1 A T and the Galerkin coarse matrix P^T A P.
//
// T maps each aggregate's (at most six) rigid-body coefficients to its nodes' displacements:
// one 3 x 6 block per node (its aggregate's orthonormal modes at the node, columns beyond the
// aggregate's rank zero). P then reaches the aggregates of a node's neighbours, and P^T A P
// couples aggregates two rings apart. Computed with 3 x 3 and 3 x 6 blocks (the products of
// fixed-size matrices vectorise, and one index serves 18 values), row by node, the products
// are a fraction of what scalar sparse products of the same matrices cost, which dominated
// the first step of large meshes (122,880 tets: see docs/notes/performance.md).
#pragma once

#include <Eigen/SparseCore>
#include <Eigen/StdVector>
#include <vector>

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

using Block36 = Eigen::Matrix<double, 3, 6>;
using Block36List = std::vector<Block36, Eigen::aligned_allocator<Block36>>;

// A 3n x 6m matrix by node rows of 3 x 6 blocks: node i's blocks are [start[i], start[i+1]),
// in ascending aggregate order.
struct NodeAggregateBlocks {
  std::vector<int> start;
  std::vector<int> aggregate;
  Block36List blocks;
};

// P = T - weight D^-1 A T, blocks that are exactly zero left out. aggregate_of_node[i] is node
// i's aggregate, tentative[i] its block of T, inverse_diagonal[i] = A_ii^-1; num_aggregates
// the number of aggregates.
NodeAggregateBlocks smoothed_prolongator(const BlockSparseMatrix& A, const std::vector<Mat3>& inverse_diagonal,
                                         const std::vector<int>& aggregate_of_node, const Block36List& tentative,
                                         int num_aggregates, double weight);

// P^T A P as a scalar symmetric matrix (both triangles, exactly symmetric): aggregate a's
// coarse DOFs are coarse_start[a] ... coarse_start[a + 1] - 1 (its rank: P's columns beyond
// it are zero).
Eigen::SparseMatrix<double, Eigen::ColMajor, int> galerkin_product(const BlockSparseMatrix& A,
                                                                   const NodeAggregateBlocks& P,
                                                                   const std::vector<int>& coarse_start);

}  // namespace corotate
