// How far each part of a body has turned since a preconditioner was built.
//
// Preconditioners built once from the first system they see (here: the two-level one's
// coarse level; the reference factor turns node by node, node_rotations.hpp) are right only
// near the configuration they were built at. When the body turns,
// the system becomes about R A0 R^T (exactly, for a rigid rotation R: the mass is isotropic
// and the co-rotational stiffness turns with the body), and a frozen A0^-1 no longer fits.
// This class groups the nodes into aggregates (a node and its neighbours in the matrix
// pattern), finds each aggregate's rotation from the build configuration by shape matching
// (the polar rotation of sum_i x_i (X_i - c)^T over its nodes); the preconditioner turns
// vectors into and out of the build frame node by node with them. A preconditioner
// B0 ~ A0^-1 then becomes R B0 R^T, exact again after a rigid rotation.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "corotate/solvers/saved_rotations.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class AggregateRotations {
 public:
  // Aggregates from the node graph of `pattern`; offsets from `built_at` (3 x n). Rotations
  // start at the identity.
  void build(const BlockSparseMatrix& pattern, const Nodes& built_at);
  // The same with given aggregates: aggregate_of_node[i] in [0, count).
  void build(const std::vector<int>& aggregate_of_node, int count, const Nodes& built_at);
  bool empty() const { return aggregate_.empty(); }
  Index num_aggregates() const { return static_cast<Index>(rotations_.size()); }
  const std::vector<int>& aggregate_of_node() const { return aggregate_; }
  // X_i - c: each node's offset from its aggregate's centre in the build configuration.
  const Nodes& offsets() const { return offsets_; }
  const Mat3& rotation(Index a) const { return rotations_[a]; }
  // Some aggregate's rotation differs from the identity.
  bool rotated() const { return rotated_; }

  // Rotations from the positions x (3 x n) by shape matching, warm-started from the last
  // ones. A one-node aggregate or a non-finite covariance keeps its previous rotation.
  void update(const Nodes& x);
  // Copies of the rotations and their warm starts, and back (a failed Simulation::step).
  void save_state() { saved_.save(rotations_, rotation_guess_, rotated_); }
  void restore_state() { saved_.restore(rotations_, rotation_guess_, rotated_); }

 private:
  std::vector<int> aggregate_;                      // aggregate of each node
  Nodes offsets_;                                   // X_i - c (build configuration minus its aggregate's centre)
  std::vector<Mat3> rotations_;                     // per aggregate
  std::vector<Mat3> covariance_;                    // work space of update()
  // Work space of build() (the linearised step builds again at every assembly of a matrix it
  // keeps: no allocation there).
  std::vector<Vec3> centre_;
  std::vector<int> size_;
  std::vector<Eigen::Quaterniond> rotation_guess_;  // warm starts of the rotation extraction
  bool rotated_ = false;
  SavedRotations saved_;
};

// Greedy aggregation of the node graph: a node whose neighbours are all free starts an
// aggregate with them; leftovers join a neighbouring aggregate. Returns the aggregate of each
// node and their number in *count.
std::vector<int> aggregate_nodes(const BlockSparseMatrix& pattern, int* count);

// The connected parts of the node graph of `pattern` (the separate bodies of a Scene): the
// part of each node, and their number in *count.
std::vector<int> connected_parts(const BlockSparseMatrix& pattern, int* count);

}  // namespace corotate
