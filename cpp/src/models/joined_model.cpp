#include "corotate/models/joined_model.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace corotate {

JoinedModel::JoinedModel(const std::vector<const ForceModel*>& parts) {
  if (parts.empty()) throw InvalidInput("joined model: no parts");
  for (const ForceModel* model : parts) {
    if (!model) throw InvalidInput("joined model: a part is missing");
    Part part;
    part.model = model->clone();
    parts_.push_back(std::move(part));
  }
  build();
}

JoinedModel::JoinedModel(const JoinedModel& other) : ForceModel(other) {
  for (const Part& p : other.parts_) {
    Part part;
    part.model = p.model->clone();
    parts_.push_back(std::move(part));
  }
  build();
}

void JoinedModel::build() {
  Index nodes = 0;
  int blocks = 0;
  std::vector<std::pair<int, int>> pairs;
  for (Part& part : parts_) {
    part.node_offset = nodes;
    part.block_offset = blocks;
    const BlockSparseMatrix& p = part.model->pattern();
    for (Index i = 0; i < p.num_nodes(); ++i)
      for (int k = p.row_start()[i]; k < p.row_start()[i + 1]; ++k)
        pairs.emplace_back(static_cast<int>(nodes + i), static_cast<int>(nodes + p.columns()[k]));
    nodes += part.model->num_nodes();
    blocks += static_cast<int>(p.num_blocks());
  }
  pattern_ = BlockSparseMatrix::from_pairs(nodes, pairs);
  // Block diagonal with sorted rows: part k's blocks are the joined ones from its block
  // offset on, in the same order (evaluate adds them as one run).
  if (pattern_.num_blocks() != blocks) throw InvalidInput("joined model: the parts' patterns do not join");
  rest_.resize(3, nodes);
  for (Part& part : parts_) {
    const Index n = part.model->num_nodes();
    rest_.middleCols(part.node_offset, n) = part.model->rest_positions();
    part.x.resize(3, n);
    part.forces_at.resize(3, n);
    part.forces.resize(3, n);
    part.stiffness = part.model->pattern();
  }
}

BlockSparseMatrix JoinedModel::mass_matrix(bool lumped) const {
  BlockSparseMatrix M = pattern_;
  M.set_zero();
  for (const Part& part : parts_) {
    const BlockSparseMatrix m = part.model->mass_matrix(lumped);
    std::copy(m.values().begin(), m.values().end(), M.values().begin() + 9 * part.block_offset);
  }
  return M;
}

bool JoinedModel::is_linear() const {
  return std::all_of(parts_.begin(), parts_.end(), [](const Part& p) { return p.model->is_linear(); });
}

bool JoinedModel::symmetric_tangent() const {
  return std::all_of(parts_.begin(), parts_.end(), [](const Part& p) { return p.model->symmetric_tangent(); });
}

bool JoinedModel::measures_frame_drift() const {
  const bool all_measure =
      std::all_of(parts_.begin(), parts_.end(), [](const Part& p) { return p.model->measures_frame_drift(); });
  const bool none_turns =
      std::none_of(parts_.begin(), parts_.end(), [](const Part& p) { return p.model->stiffness_turns(); });
  return all_measure && (stiffness_turns() || none_turns);
}

bool JoinedModel::stiffness_turns() const {
  return std::all_of(parts_.begin(), parts_.end(), [](const Part& p) { return p.model->stiffness_turns(); });
}

void JoinedModel::evaluate(const Nodes& x, const Request& what, Results& out) {
  check_evaluation(x, what, out);
  Request part_request = what;
  // Every block of each part: which blocks the joined product reads depends on the joined
  // pattern's row chunks, not on the part's.
  part_request.lower_blocks = true;
  double energy = 0, drift = 0;
  Index inverted = 0;
  for (Part& part : parts_) {
    const Index n = part.model->num_nodes();
    part.x = x.middleCols(part.node_offset, n);
    if (what.forces_at) {
      part.forces_at = what.forces_at->middleCols(part.node_offset, n);
      part_request.forces_at = &part.forces_at;
    }
    if (what.frame_turn_of_node) part_request.frame_turn_of_node = what.frame_turn_of_node + part.node_offset;
    Results part_out;
    if (what.forces) {
      part.forces.setZero();
      part_out.forces = &part.forces;
    }
    if (what.stiffness != StiffnessKind::None) {
      part.stiffness.set_zero();
      part_out.stiffness = &part.stiffness;
    }
    part.model->evaluate(part.x, part_request, part_out);
    energy += part_out.energy;
    inverted += part_out.inverted;
    drift = std::max(drift, part_out.frame_drift);
    if (what.forces) out.forces->middleCols(part.node_offset, n) += part.forces;
    if (what.stiffness != StiffnessKind::None) {
      const std::vector<double>& from = part.stiffness.values();
      double* to = out.stiffness->values().data() + 9 * static_cast<size_t>(part.block_offset);
      for (size_t i = 0; i < from.size(); ++i) to[i] += from[i];
    }
  }
  if (what.energy) out.energy = energy;
  if (what.count_inverted) out.inverted = inverted;
  if (what.frame_drift) out.frame_drift = drift;
}

void JoinedModel::save_caches() {
  for (Part& part : parts_) part.model->save_caches();
}

void JoinedModel::restore_caches() {
  for (Part& part : parts_) part.model->restore_caches();
}

void JoinedModel::reset_caches() {
  for (Part& part : parts_) part.model->reset_caches();
}

}  // namespace corotate
