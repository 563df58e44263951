// Several bodies' force models side by side: one model over their nodes one body after the
// other (body k's nodes at offset(k) on), so that one simulation steps bodies of different
// cell types or force models together (a Scene of a co-rotated tet body and a Neo-Hookean
// hex body, say). The bodies share no node and no element: the pattern is block diagonal,
// and its value array is the parts' value arrays one after the other, so a part's stiffness
// is added to the joined matrix as one contiguous run.
//
// Each part evaluates into its own buffers (its positions, forces and matrix), which are then
// added to the joined ones: a copy of each part's blocks per evaluation, the price of parts
// whose kernels know nothing of each other. Those buffers are sized once; evaluate()
// allocates nothing. The float32 fast path of a single co-rotated tet model is not offered
// (assembles_single_precision false): the step assembles in double and converts.
#pragma once

#include <memory>
#include <vector>

#include "corotate/models/force_model.hpp"

namespace corotate {

class JoinedModel final : public ForceModel {
 public:
  // The parts are cloned (each keeps its own precomputed element data). Throws InvalidInput
  // for no parts.
  explicit JoinedModel(const std::vector<const ForceModel*>& parts);
  JoinedModel(const JoinedModel& other);
  JoinedModel& operator=(const JoinedModel&) = delete;

  const char* name() const override { return "joined"; }
  std::unique_ptr<ForceModel> clone() const override { return std::make_unique<JoinedModel>(*this); }
  Index num_nodes() const override { return rest_.cols(); }
  const Nodes& rest_positions() const override { return rest_; }
  const BlockSparseMatrix& pattern() const override { return pattern_; }
  BlockSparseMatrix mass_matrix(bool lumped) const override;
  bool is_linear() const override;
  bool symmetric_tangent() const override;
  // When every part does and all parts turn or none (one kept system turns all or none).
  bool measures_frame_drift() const override;
  bool stiffness_turns() const override;
  void evaluate(const Nodes& x, const Request& what, Results& out) override;
  void save_caches() override;
  void restore_caches() override;
  void reset_caches() override;

  Index num_parts() const { return static_cast<Index>(parts_.size()); }
  const ForceModel& part(Index k) const { return *parts_[k].model; }
  Index node_offset(Index k) const { return parts_[k].node_offset; }

 private:
  struct Part {
    std::unique_ptr<ForceModel> model;
    Index node_offset = 0;
    int block_offset = 0;
    // Work buffers of one evaluation, sized at construction.
    Nodes x, forces_at, forces;
    BlockSparseMatrix stiffness;
  };
  void build();  // the rest positions, pattern and buffers from parts_' models and offsets
  std::vector<Part> parts_;
  Nodes rest_;
  BlockSparseMatrix pattern_;
};

}  // namespace corotate
