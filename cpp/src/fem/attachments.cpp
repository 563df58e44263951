#include "corotate/fem/attachments.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate {

void Attachments::check_nodes(const std::vector<Index>& nodes, bool must_be_attached) const {
  const Index n = static_cast<Index>(slot_.size());
  std::vector<char> seen;
  for (Index i : nodes) {
    std::ostringstream msg;
    if (i < 0 || i >= n) msg << "node index " << i << " is out of range [0, " << n << ")";
    else if (must_be_attached && slot_[i] < 0) msg << "node " << i << " is not attached";
    if (msg.tellp() > 0) throw InvalidInput(msg.str());
    if (seen.empty()) seen.assign(n, 0);
    if (seen[i]) throw InvalidInput("node " + std::to_string(i) + " is listed twice");
    seen[i] = 1;
  }
}

void Attachments::check_targets(const std::vector<Index>& nodes, const Nodes& targets) {
  if (targets.cols() != static_cast<Index>(nodes.size())) {
    std::ostringstream msg;
    msg << "need one target per node: " << nodes.size() << " nodes, " << targets.cols() << " targets";
    throw InvalidInput(msg.str());
  }
  if (Index a = first_non_finite_node(targets); a >= 0)
    throw InvalidInput("the target of node " + std::to_string(nodes[a]) + " is not finite");
}

void Attachments::attach(const std::vector<Index>& nodes, const Nodes& targets, const Vec& stiffness) {
  check_nodes(nodes, false);
  check_targets(nodes, targets);
  if (stiffness.size() != static_cast<Index>(nodes.size()))
    throw InvalidInput("need one stiffness per node (or one for all)");
  for (Index a = 0; a < stiffness.size(); ++a)
    if (!(stiffness[a] > 0) || !std::isfinite(stiffness[a])) {
      std::ostringstream msg;
      msg << "the attachment stiffness of node " << nodes[a] << " must be positive and finite, got " << stiffness[a];
      throw InvalidInput(msg.str());
    }
  Index added = 0;
  for (Index i : nodes) added += slot_[i] < 0;
  const Index m = size();
  targets_.conservativeResize(3, m + added);
  stiffness_.conservativeResize(m + added);
  for (size_t a = 0; a < nodes.size(); ++a) {
    const Index i = nodes[a];
    if (slot_[i] < 0) {
      slot_[i] = static_cast<int>(nodes_.size());
      nodes_.push_back(i);
    }
    targets_.col(slot_[i]) = targets.col(a);
    stiffness_[slot_[i]] = stiffness[a];
  }
  ++version_;
  ++stiffness_version_;
}

void Attachments::move(const std::vector<Index>& nodes, const Nodes& targets) {
  check_nodes(nodes, true);
  check_targets(nodes, targets);
  for (size_t a = 0; a < nodes.size(); ++a) targets_.col(slot_[nodes[a]]) = targets.col(a);
  ++version_;
}

void Attachments::detach(const std::vector<Index>& nodes) {
  check_nodes(nodes, true);
  for (Index i : nodes) {
    // Move the last spring into the freed slot.
    const int s = slot_[i], last = static_cast<int>(nodes_.size()) - 1;
    nodes_[s] = nodes_[last];
    targets_.col(s) = targets_.col(last);
    stiffness_[s] = stiffness_[last];
    slot_[nodes_[s]] = s;
    slot_[i] = -1;
    nodes_.pop_back();
  }
  targets_.conservativeResize(3, size());
  stiffness_.conservativeResize(size());
  ++version_;
  ++stiffness_version_;
}

void Attachments::clear() {
  for (Index i : nodes_) slot_[i] = -1;
  nodes_.clear();
  targets_.resize(3, 0);
  stiffness_.resize(0);
  ++version_;
  ++stiffness_version_;
}

void Attachments::add_forces(const Nodes& x, Nodes& f) const {
  for (Index a = 0; a < size(); ++a) f.col(nodes_[a]) += stiffness_[a] * (targets_.col(a) - x.col(nodes_[a]));
}

void Attachments::add_stiffness(double scale, BlockSparseMatrix& A) const {
  for (Index a = 0; a < size(); ++a) A.block(A.diagonal_block(nodes_[a])).diagonal().array() += scale * stiffness_[a];
}

void Attachments::add_stiffness(double scale, SinglePrecisionSymmetric& A) const {
  for (Index a = 0; a < size(); ++a) A.add_to_diagonal(nodes_[a], scale * stiffness_[a]);
}

double Attachments::energy(const Nodes& x) const {
  double e = 0;
  for (Index a = 0; a < size(); ++a) e += 0.5 * stiffness_[a] * (x.col(nodes_[a]) - targets_.col(a)).squaredNorm();
  return e;
}

double Attachments::max_rate(const Vec& masses) const {
  double rate = 0;
  for (Index a = 0; a < size(); ++a) rate = std::max(rate, stiffness_[a] / masses[nodes_[a]]);
  return rate;
}

}  // namespace corotate
