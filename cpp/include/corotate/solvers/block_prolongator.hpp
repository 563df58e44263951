// The prolongator P of the two-level preconditioner in node x aggregate blocks, one stored
// copy for both of its products, P c and P^T r.
//
// P maps each aggregate's (at most) six rigid-body coefficients to the three displacements
// of every node it reaches, so it is made of 3 x 6 blocks: one per (node, aggregate) pair,
// stored node by node with one aggregate index per block. Against two scalar CSR copies (P
// and P^T, a column index per entry) this reads one index per block of 18 values and less
// storage. P c runs over nodes (each thread writes its own nodes); P^T r runs over
// aggregates, each gathering its blocks through a list built once, so both are the same sum
// in the same order on any number of threads. The values are stored in float32 (summed in
// double): P is fixed after setup and only shapes a preconditioner, and at 122,880 tets its
// 13 MB (in double) are read twice per application, bandwidth-bound.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

#include "corotate/common.hpp"
#include "corotate/solvers/smoothed_aggregation.hpp"

namespace corotate {

class BlockProlongator {
 public:
  using ScalarMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

  BlockProlongator() = default;
  // P: 3 num_nodes x coarse DOFs; coarse_start: first coarse DOF of each aggregate
  // (num_aggregates + 1 entries, at most 6 DOFs each). Every entry of P must lie in a
  // column of some aggregate (InvalidInput otherwise).
  BlockProlongator(const ScalarMatrix& P, const std::vector<int>& coarse_start);
  // The same from P's blocks (smoothed_aggregation.hpp); columns beyond an aggregate's coarse
  // DOFs are left out.
  BlockProlongator(const NodeAggregateBlocks& P, const std::vector<int>& coarse_start);

  Index num_nodes() const { return static_cast<Index>(node_start_.size()) - 1; }
  Index num_aggregates() const { return static_cast<Index>(coarse_start_.size()) - 1; }
  Index num_blocks() const { return static_cast<Index>(block_aggregate_.size()); }
  Index coarse_size() const { return coarse_start_.empty() ? 0 : coarse_start_.back(); }

  // Node i's blocks are [node_begin(i), node_end(i)); block k's aggregate and its values
  // (columns beyond the aggregate's coarse DOFs are zero).
  int node_begin(Index i) const { return node_start_[i]; }
  int node_end(Index i) const { return node_start_[i + 1]; }
  int block_aggregate(int k) const { return block_aggregate_[k]; }
  Eigen::Matrix<double, 3, 6> block(int k) const;

  // fine = P coarse, or fine += P coarse when add. No allocation after the first call.
  void prolong(const Vec& coarse, Vec& fine, bool add);
  // coarse = P^T fine.
  void restrict_to(const Vec& fine, Vec& coarse);

 private:
  void index_by_aggregate();  // the aggregate lists below, from node_start_ and block_aggregate_
  std::vector<int> coarse_start_;     // per aggregate, + 1
  std::vector<int> node_start_;       // first block of each node, + 1
  std::vector<int> block_aggregate_;  // aggregate of each block
  // 24 per block: the 3 x 6 block in float32, each row padded with two zeros to eight
  // values, so that a row times an aggregate's coarse values is one eight-wide multiply.
  std::vector<float> values_;
  std::vector<int> aggregate_start_;  // first entry of each aggregate in the lists below, + 1
  std::vector<int> aggregate_block_, aggregate_node_;  // its blocks and their nodes
  // The coarse vector with six entries per aggregate and two zeros (eight per aggregate), in
  // float32 like the values: both products sum in float32 (relative 1e-7 of a sum of |p||r| in a preconditioner; no
  // widening of each value).
  Eigen::VectorXf padded_;
};

}  // namespace corotate
