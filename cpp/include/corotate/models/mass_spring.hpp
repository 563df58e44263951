// Mass-spring system (paper §2.1): point masses joined by linear springs, with the elastic
// force of eq. (1) and the damping force of eq. (2), both acting along the spring.
//
// For a spring s = (i, j) with stiffness k, damping d and rest length l0, and
// e = x_j - x_i, l = |e|, u = e / l:
//   elastic  f_i = k (l - l0) u                          (eq. 1),   f_j = -f_i
//   damping  f_i = d (u . (v_j - v_i)) u                 (eq. 2),   f_j = -f_i
//   energy   E_s = k (l - l0)^2 / 2
//   Hessian  H_s = k [u u^T + (1 - l0 / l) (I - u u^T)],  K = -df/dx has blocks
//            K_ii = K_jj = H_s, K_ij = K_ji = -H_s (exact, so compressed springs make K
//            indefinite; an implicit integrator may want to clamp 1 - l0/l at zero).
// Both eigenvalues of H_s (k and k (1 - l0/l)) are at most k in every configuration, so
// the "spring Laplacian" L_k (x) I with blocks k I is an upper bound of K for every x:
// add_stiffness_bound (ExplicitTraits) gives it, and the critical time step taken from it is safe for any
// configuration the system can reach (the conservative policy of the paper). The same
// holds for the damping matrix C (blocks d u u^T) and d I.
//
// The mass matrix is diagonal (one point mass per node) whether lumped or not.
#pragma once

#include <array>
#include <vector>

#include "corotate/models/explicit_traits.hpp"
#include "corotate/models/force_model.hpp"

namespace corotate {

struct Spring {
  int i = 0, j = 0;          // node indices, i != j
  double stiffness = 0;      // k  [N/m], >= 0
  double damping = 0;        // d  [N s/m], >= 0
  double rest_length = 0;    // l0 [m], >= 0
};

class MassSpring final : public ForceModel, public ExplicitTraits {
 public:
  // rest: 3 x n node positions; springs; masses: n point masses [kg].
  // Throws InvalidInput naming the node or spring: mass <= 0 or not finite, node index out
  // of range, a spring joining a node to itself or two coincident nodes (its direction is
  // undefined), k, d or l0 negative or not finite.
  MassSpring(const Nodes& rest, std::vector<Spring> springs, const Vec& masses);

  const char* name() const override { return "mass_spring"; }
  std::unique_ptr<ForceModel> clone() const override { return std::make_unique<MassSpring>(*this); }
  Index num_nodes() const override { return rest_.cols(); }
  const Nodes& rest_positions() const override { return rest_; }
  const BlockSparseMatrix& pattern() const override { return pattern_; }
  // Diagonal blocks m_i I for both kinds (point masses have no consistent form).
  BlockSparseMatrix mass_matrix(bool lumped) const override;
  bool is_linear() const override { return false; }
  // Model and Tangent stiffness are both the exact Hessian; no Geometric stiffness.
  void evaluate(const Nodes& x, const Request& what, Results& out) override;
  const ExplicitTraits* explicit_traits() const override { return this; }

  // f += damping forces of eq. (2) at positions x and velocities v (3 x n).
  void add_damping_forces(const Nodes& x, const Nodes& v, Nodes& f) const;
  // ExplicitTraits: elastic + damping forces in one sweep over the springs; C at x (blocks
  // d u u^T); L_k (x) I and L_d (x) I, the configuration-independent upper bounds of K and
  // C (see the note at the top of this file).
  bool has_damping() const override;
  void add_forces_and_damping(const Nodes& x, const Nodes& v, Nodes& f) const override;
  void add_damping_matrix(const Nodes& x, double scale, BlockSparseMatrix& A) const override;
  void add_stiffness_bound(double scale, BlockSparseMatrix& A) const override;
  void add_damping_bound(double scale, BlockSparseMatrix& A) const override;

  const std::vector<Spring>& springs() const { return springs_; }
  const Vec& masses() const { return masses_; }
  Index num_springs() const { return static_cast<Index>(springs_.size()); }

 private:
  template <class BlockOf>
  void scatter(double scale, BlockSparseMatrix& A, BlockOf block_of) const;

  Nodes rest_;
  std::vector<Spring> springs_;
  Vec masses_;
  BlockSparseMatrix pattern_;
  std::vector<std::array<int, 4>> blocks_;  // per spring: block indices of (i,i), (j,j), (i,j), (j,i)
};

}  // namespace corotate
