// How far the neighbourhood of each node has turned since a preconditioner was built.
//
// The reference factor (preconditioner.hpp) is a factor of the system A0 a body had when it
// was built; once the body turns, its system is about R A0 R^T with R the rotation of each
// element. Turning the frozen factor by one rotation per node, z = R B0 R^T r, fits that
// best where R follows the elements closely: per node, this class takes the polar rotation
// of sum_j x_j (X_j - c_i)^T over the node's stencil (itself and its neighbours in the
// matrix pattern; X the build positions, c_i their centre), i.e. shape matching of its
// neighbourhood. On the Table 1 cage that took CG from 3.05 to 1.93 iterations per step
// against one rotation per aggregate of about ten nodes (AggregateRotations, which the
// two-level preconditioner keeps for its coarse space). A rigid rotation turns every stencil
// by itself, so the turned factor is exact again after one.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "corotate/solvers/saved_rotations.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class NodeRotations {
 public:
  // Stencils from the pattern's rows, offsets X_j - c_i from `built_at` (3 x n). Rotations
  // start at the identity.
  void build(const BlockSparseMatrix& pattern, const Nodes& built_at);
  bool empty() const { return rotations_.empty(); }
  // Rotations from the positions x (3 x n), warm-started from the last ones. A stencil whose
  // covariance is zero or not finite keeps its node's previous rotation.
  void update(const Nodes& x);
  // Some node's rotation differs from the identity.
  bool rotated() const { return rotated_; }
  // One per node.
  const std::vector<Mat3>& rotations() const { return rotations_; }
  // Copies of the rotations and their warm starts, and back (a failed Simulation::step).
  void save_state() { saved_.save(rotations_, guess_, rotated_); }
  void restore_state() { saved_.restore(rotations_, guess_, rotated_); }

 private:
  std::vector<int> start_, stencil_;  // node i's stencil: stencil_[start_[i] .. start_[i + 1])
  std::vector<double> offsets_;       // X_j - c_i, three per stencil entry
  std::vector<Mat3> covariance_;      // work space of update()
  std::vector<Mat3> rotations_;
  std::vector<Eigen::Quaterniond> guess_;  // warm starts of the rotation extraction
  bool rotated_ = false;
  SavedRotations saved_;
};

}  // namespace corotate
