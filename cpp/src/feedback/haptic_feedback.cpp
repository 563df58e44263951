#include "corotate/feedback/haptic_feedback.hpp"

#include <sstream>
#include <unordered_map>

#include "corotate/models/model_factory.hpp"

namespace corotate {

const std::vector<std::string>& feedback_method_names() {
  static const std::vector<std::string> names = {"linear", "corotational", "averaged"};
  return names;
}

FeedbackMethod feedback_method_from_name(const std::string& name) {
  const auto& names = feedback_method_names();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<FeedbackMethod>(i);
  throw InvalidInput("unknown feedback method '" + name + "' (choose 'linear', 'corotational' or 'averaged')");
}

HapticFeedback::HapticFeedback(const std::string& cell_type, const Nodes& rest, const Connectivity& cells,
                               const RegionMaterials& materials, const std::vector<Index>& tool, FeedbackMethod method,
                               const ModelOptions& options)
    : tool_(tool), method_(method) {
  const Index n = rest.cols();
  if (tool.empty()) throw InvalidInput("the tool needs at least one node");
  std::vector<char> in_tool(n, 0);
  for (Index i : tool) {
    if (i < 0 || i >= n) {
      std::ostringstream msg;
      msg << "tool node " << i << " is out of range [0, " << n << ")";
      throw InvalidInput(msg.str());
    }
    if (in_tool[i]) throw InvalidInput("tool node " + std::to_string(i) + " is listed twice");
    in_tool[i] = 1;
  }
  // The elements that touch the tool, renumbered locally.
  std::unordered_map<Index, Index> local_of;
  std::vector<Index> elements;
  for (Index e = 0; e < cells.rows(); ++e) {
    bool touches = false;
    for (Index a = 0; a < cells.cols(); ++a) {
      const Index node = cells(e, a);
      touches = touches || (node >= 0 && node < n && in_tool[node]);
    }
    if (touches) elements.push_back(e);
  }
  Connectivity local_cells(static_cast<Index>(elements.size()), cells.cols());
  for (size_t k = 0; k < elements.size(); ++k)
    for (Index a = 0; a < cells.cols(); ++a) {
      const Index node = cells(elements[k], a);
      auto [it, inserted] = local_of.emplace(node, static_cast<Index>(local_to_global_.size()));
      if (inserted) local_to_global_.push_back(node);
      local_cells(static_cast<Index>(k), a) = static_cast<int>(it->second);
    }
  for (Index i : tool) {
    const auto it = local_of.find(i);
    if (it == local_of.end()) throw InvalidInput("tool node " + std::to_string(i) + " belongs to no element");
    tool_local_.push_back(it->second);
  }
  num_elements_ = static_cast<Index>(elements.size());
  Nodes local_rest(3, static_cast<Index>(local_to_global_.size()));
  for (size_t j = 0; j < local_to_global_.size(); ++j)
    local_rest.col(static_cast<Index>(j)) = rest.col(local_to_global_[j]);
  static const char* const kModel[] = {"linear", "corotational", "stvk"};  // Averaged: see the header
  // The tool's elements keep their materials, given by their small-strain moduli (the
  // averaged method's StVK takes E and nu whatever the body's law).
  materials.validate(cells.rows());
  RegionMaterials local_materials = materials.of_cells(elements);
  for (Material& m : local_materials.materials) m = m.small_strain();
  local_ = make_model(kModel[static_cast<int>(method)], cell_type, local_rest, local_cells, local_materials, options);
  K_local_ = local_->pattern();
  const Index k = static_cast<Index>(tool.size());
  tool_blocks_.resize(k * k);
  for (Index a = 0; a < k; ++a)
    for (Index b = 0; b < k; ++b) tool_blocks_[a * k + b] = K_local_.block_index(tool_local_[a], tool_local_[b]);
  x_local_ = local_rest;
  f_local_.setZero(3, local_rest.cols());
}

void HapticFeedback::query(const Nodes& x, Nodes& forces, Eigen::MatrixXd& stiffness) {
  for (size_t j = 0; j < local_to_global_.size(); ++j) {
    if (local_to_global_[j] >= x.cols()) throw InvalidInput("feedback query: positions have too few nodes");
    x_local_.col(static_cast<Index>(j)) = x.col(local_to_global_[j]);
  }
  if (!x_local_.allFinite()) throw InvalidInput("feedback query: a position near the tool is not finite");
  f_local_.setZero();
  K_local_.set_zero();
  Request what;
  what.forces = true;
  what.stiffness = StiffnessKind::Tangent;
  Results out;
  out.forces = &f_local_;
  out.stiffness = &K_local_;
  local_->evaluate(x_local_, what, out);
  const Index k = static_cast<Index>(tool_.size());
  forces.resize(3, k);
  stiffness.resize(3 * k, 3 * k);
  for (Index a = 0; a < k; ++a) {
    forces.col(a) = f_local_.col(tool_local_[a]);
    for (Index b = 0; b < k; ++b) {
      const int block = tool_blocks_[a * k + b];
      // dF/dx = -K (K = -df/dx)
      if (block >= 0) stiffness.block<3, 3>(3 * a, 3 * b) = -K_local_.block(block);
      else stiffness.block<3, 3>(3 * a, 3 * b).setZero();
    }
  }
}

}  // namespace corotate
