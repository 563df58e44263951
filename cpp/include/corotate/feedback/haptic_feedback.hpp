// Force feedback at a small set of nodes (paper section 2.2.3): the force the body exerts on
// a tool (a set of prescribed nodes) and its local stiffness, from only the elements that
// touch the tool, at haptic rates (about 1 kHz) while the body itself steps at 100-500 Hz.
//
// The elements around the tool are copied once into a small model of their own (local node
// numbering), built with the chosen method:
//   Linear        f = -K_e (x_e - X_e): wrong under rotation;
//   Corotational  eq. (3), f = -R_e K_e (R_e^T x_e - X_e): right under rotation, but linear in
//                 the element's local frame, so the force misses the stiffening (and
//                 softening) of large stretch;
//   Averaged      eq. (5), the paper's averaged (secant) stiffness
//                     tK_e = integral of tB_e^T H tB_e,1/2 dV,   f = R_e tK_e u,
//                 u = R_e^T x_e - X_e the total rotation-free displacement.
// What eq. (5) computes: with the strain-displacement matrix of a configuration read as the
// total-Lagrangian one, B(u) du = dE = sym(F(u)^T grad du), F(u) = I + grad u, the matrix of
// the mid configuration gives B(u/2) u = sym((I + grad u / 2)^T grad u)
//     = sym(grad u) + 1/2 grad u^T grad u = E(u),
// exactly the Green-Lagrange strain (in 1D: (1 + u'/2) u' = u' + u'^2/2). So H B_1/2 u is the
// second Piola-Kirchhoff stress S = H E of St. Venant-Kirchhoff, and tB_e^T S integrated over
// the rest volume is the total-Lagrangian StVK internal force of the rotation-free element.
// StVK is frame-indifferent (f(Q x) = Q f(x)), so rotating back with R_e gives the StVK force
// of the element itself: the averaged stiffness is the secant form of StVK, exact for any
// rotation and any stretch in this reading (the paper's alternative, averaging the linear B
// of the original and the rotation-free geometry, agrees with it to second order in the
// strain). It is therefore computed with the StVK kernel (hyperelastic_kernel.hpp).
//
// The stiffness returned is dF/dx of the forces on the tool nodes with respect to their
// positions (the Tangent kind of each method: exact for linear, co-rotated tets and StVK),
// what a haptic loop needs to render a stiff contact stably between two queries.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "corotate/fem/element_kernel.hpp"
#include "corotate/models/force_model.hpp"

namespace corotate {

enum class FeedbackMethod { Linear, Corotational, Averaged };
const std::vector<std::string>& feedback_method_names();  // "linear", "corotational", "averaged"
FeedbackMethod feedback_method_from_name(const std::string& name);

class HapticFeedback {
 public:
  // The body's mesh (rest: 3 x n, cells: m x k of cell_type) and materials (one, or one per
  // region with each cell's region; every method uses their small-strain moduli E and nu);
  // tool: node indices (distinct, in range). Throws InvalidInput naming what is wrong.
  HapticFeedback(const std::string& cell_type, const Nodes& rest, const Connectivity& cells,
                 const RegionMaterials& materials, const std::vector<Index>& tool, FeedbackMethod method,
                 const ModelOptions& options = ModelOptions());

  // At positions x (3 x n, the whole body's; only the nodes of the tool's elements are read):
  // forces (3 x k), the force the body exerts on each tool node (its internal elastic force);
  // stiffness (3k x 3k), dF/dx. No allocation after the first call.
  void query(const Nodes& x, Nodes& forces, Eigen::MatrixXd& stiffness);

  const std::vector<Index>& tool() const { return tool_; }
  Index num_elements() const { return num_elements_; }  // elements touching the tool
  FeedbackMethod method() const { return method_; }

 private:
  std::vector<Index> tool_;
  FeedbackMethod method_;
  Index num_elements_ = 0;
  std::unique_ptr<ForceModel> local_;  // the tool's elements, local node numbering
  std::vector<Index> local_to_global_;
  std::vector<Index> tool_local_;      // local index of each tool node
  std::vector<int> tool_blocks_;       // k x k block indices in the local pattern, -1 where uncoupled
  Nodes x_local_, f_local_;
  BlockSparseMatrix K_local_;
};

}  // namespace corotate
