// Implicit attachments: zero-rest-length springs pulling nodes towards targets (a vertex
// grabbed with the mouse, a haptic tool). Spring a on node n with stiffness k and target t
// adds to the body's
//     energy 1/2 k |x_n - t|^2,   force k (t - x_n),   stiffness k I on the diagonal block (n, n).
// The implicit integrators put that stiffness into their system matrix, so a spring of any
// stiffness is as stable as a fixed node; the explicit integrators add the force and bound
// the stable step with it (explicit_integrator.hpp). Only diagonal blocks are touched, which
// every pattern has: attaching, moving and detaching rebuild nothing (no pattern, no
// factorization, no preconditioner hierarchy), they change these arrays only.
// A node that is also fixed stays fixed: the projection of fixed DOFs comes after.
#pragma once

#include <vector>

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class SinglePrecisionSymmetric;

class Attachments {
 public:
  Attachments() = default;
  explicit Attachments(Index num_nodes) : slot_(num_nodes, -1) {}

  bool empty() const { return nodes_.empty(); }
  Index size() const { return static_cast<Index>(nodes_.size()); }
  const std::vector<Index>& nodes() const { return nodes_; }
  const Nodes& targets() const { return targets_; }  // 3 x size()
  const Vec& stiffness() const { return stiffness_; }
  // Incremented by every change, so a caller can tell whether the springs moved since it looked.
  long long version() const { return version_; }
  // Incremented by the changes of the springs' stiffness (attach, detach, clear; not move):
  // whether a system matrix that holds them is still right.
  long long stiffness_version() const { return stiffness_version_; }

  // Attach nodes (or re-attach: a node attached already gets the new target and stiffness).
  // targets: 3 x nodes.size(); stiffness: nodes.size() values [N/m]. Throws InvalidInput
  // (nothing changed) for an index out of range, a node listed twice, a non-finite target or
  // a stiffness that is not positive and finite.
  void attach(const std::vector<Index>& nodes, const Nodes& targets, const Vec& stiffness);
  // New targets for attached nodes (3 x nodes.size()); throws InvalidInput (nothing changed)
  // for a node that is not attached or a non-finite target.
  void move(const std::vector<Index>& nodes, const Nodes& targets);
  // Release the listed nodes (throws InvalidInput, nothing changed, for one not attached).
  void detach(const std::vector<Index>& nodes);
  void clear();

  // f += spring forces at positions x (3 x n each).
  void add_forces(const Nodes& x, Nodes& f) const;
  // A += scale * k I on the attached nodes' diagonal blocks.
  void add_stiffness(double scale, BlockSparseMatrix& A) const;
  void add_stiffness(double scale, SinglePrecisionSymmetric& A) const;  // the same, in float32
  double energy(const Nodes& x) const;
  // max k / m over the attached nodes (masses: per node): the springs' share of omega_max^2.
  double max_rate(const Vec& masses) const;

 private:
  void check_nodes(const std::vector<Index>& nodes, bool must_be_attached) const;
  static void check_targets(const std::vector<Index>& nodes, const Nodes& targets);

  std::vector<int> slot_;  // per node: its spring, or -1
  std::vector<Index> nodes_;
  Nodes targets_;
  Vec stiffness_;
  long long version_ = 0;
  long long stiffness_version_ = 0;
};

}  // namespace corotate
