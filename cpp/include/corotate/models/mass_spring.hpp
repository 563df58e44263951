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
// add_stiffness_bound gives it, and the critical time step taken from it is safe for any
// configuration the system can reach (the conservative policy of the paper). The same
// holds for the damping matrix C (blocks d u u^T) and d I.
//
// The mass matrix is diagonal (one point mass per node) whether lumped or not.
#pragma once

#include <array>
#include <vector>

#include "corotate/models/force_model.hpp"

namespace corotate {

struct Spring {
  int i = 0, j = 0;          // node indices, i != j
  double stiffness = 0;      // k  [N/m], >= 0
  double damping = 0;        // d  [N s/m], >= 0
  double rest_length = 0;    // l0 [m], >= 0
};

class MassSpring : public ForceModel {
 public:
  // rest: 3 x n node positions; springs; masses: n point masses [kg].
  // Throws InvalidInput naming the node or spring: mass <= 0 or not finite, node index out
  // of range, a spring joining a node to itself or two coincident nodes (its direction is
  // undefined), k, d or l0 negative or not finite.
  MassSpring(const Nodes& rest, std::vector<Spring> springs, const Vec& masses);

  const char* name() const override { return "mass_spring"; }
  Index num_nodes() const override { return rest_.cols(); }
  const Nodes& rest_positions() const override { return rest_; }
  const BlockSparseMatrix& pattern() const override { return pattern_; }
  // Diagonal blocks m_i I for both kinds (point masses have no consistent form).
  BlockSparseMatrix mass_matrix(bool lumped) const override;
  bool is_linear() const override { return false; }

  // Remembers x for the stiffness and the linearised forces (forces do not need it).
  void update(const Nodes& x) override { x_ = x; }
  void add_forces(const Nodes& x, Nodes& f) const override;
  void add_stiffness(double scale, BlockSparseMatrix& A) const override;
  void add_linearized_forces(const Nodes& y, Nodes& f) const override;
  double energy(const Nodes& x) const override;

  // f += damping forces of eq. (2) at positions x and velocities v (3 x n).
  void add_damping_forces(const Nodes& x, const Nodes& v, Nodes& f) const;
  // f += elastic + damping forces in one sweep over the springs (what explicit steps use).
  void add_forces_and_damping(const Nodes& x, const Nodes& v, Nodes& f) const;
  // Explicit steps: forces need no update, so none is made (no copy of x per substep).
  void add_explicit_forces(const Nodes& x, const Nodes& v, Nodes& f) override { add_forces_and_damping(x, v, f); }
  Vec lumped_masses() const override { return masses_; }
  bool has_damping() const override;
  // A += scale * C with C = -df_damping/dv at the state of the last update (blocks d u u^T).
  void add_damping_matrix(double scale, BlockSparseMatrix& A) const override;
  // A += scale * (L_k (x) I), resp. (L_d (x) I): configuration-independent upper bounds of K
  // and C (see the note at the top of this file).
  bool add_stiffness_bound(double scale, BlockSparseMatrix& A) const override;
  bool add_damping_bound(double scale, BlockSparseMatrix& A) const override;

  const std::vector<Spring>& springs() const { return springs_; }
  const Vec& masses() const { return masses_; }
  Index num_springs() const { return static_cast<Index>(springs_.size()); }

 private:
  template <class BlockOf>
  void scatter(double scale, BlockSparseMatrix& A, BlockOf block_of) const;

  Nodes rest_, x_;
  std::vector<Spring> springs_;
  Vec masses_;
  BlockSparseMatrix pattern_;
  std::vector<std::array<int, 4>> blocks_;  // per spring: block indices of (i,i), (j,j), (i,j), (j,i)
};

}  // namespace corotate
