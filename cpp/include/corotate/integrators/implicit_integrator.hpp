// What the implicit integrators share: the mass matrix, the system matrix A in the model's
// pattern, work vectors, and the warm start dv of the linear solve (part of the state a
// failed step restores).
//
// "linearized" (linearized_implicit_euler.cpp): one linear solve per step (Baraff & Witkin
// 1998). Backward Euler asks for
//     M dv = dt (f(x + dx) - C (v + dv) + f_ext),   dx = dt (v + dv).
// Linearising the elastic force at the start of the step, f(x + dx) ~ f(x) - K dx, with K
// the model's stiffness (for the co-rotational model R K_e R^T at the current rotations):
//     (M + dt C + dt^2 K) dv = dt (f(x) + f_ext - C v) - dt^2 K v.
// With Rayleigh damping C = alpha M + beta K the system matrix is
//     A = (1 + dt alpha) M + (dt^2 + dt beta) K,
// and the right-hand side is b = dt (f(x) + f_ext) - (A - M) v. Then v <- v + dv and
// x <- x + dt v (the new velocity: the step is implicit in both).
//
// "newton" (newton_implicit_euler.cpp): the step solved to convergence. Backward Euler is
// the minimiser of the incremental potential
//     Phi(x) = 1/(2 dt^2) |x - x_n - dt v_n|_M^2 + alpha/(2 dt) |x - x_n|_M^2 + E(x) - f_ext.x,
// whose gradient is M (x - x_n - dt v_n)/dt^2 + alpha M (x - x_n)/dt - f(x) - f_ext and whose
// Hessian is (1/dt^2 + alpha/dt) M + K(x). Each Newton iteration solves Hessian dx = -gradient
// with the exact tangent (the model's PSD stiffness where the tangent is not positive
// definite) and backtracks along dx until Phi decreases enough (Armijo). It stops when
// |gradient| <= newton_tolerance * max(|f_ext| + |M v_n| / dt, |f(x_n)|) on the free DOFs;
// then v = (x - x_n) / dt. Stiffness-proportional damping is not a potential and is refused.
// Co-rotated hexes have no energy whose gradient is their force (their exact tangent is not
// symmetric, ForceModel::symmetric_tangent()): for them the "gradient" is the residual of
// the step's equations, the system is solved by sparse LU and the line search is Armijo on
// |gradient|^2 instead of Phi (on Phi it stalled: 1/2 u^T K_e u is not their potential).
// Fixed DOFs keep dv = 0 (their velocity) by projection (see FixedDofs). Both integrators
// count the attachment springs (fem/attachments.hpp) as part of the body: their energy in E,
// their force in f, their stiffness k I in K, so a grab of any stiffness is stable.
#pragma once

#include <cstdint>

#include "corotate/integrators/integrator.hpp"
#include "corotate/integrators/kept_system.hpp"
#include "corotate/solvers/aggregate_rotations.hpp"

namespace corotate {

class ImplicitIntegrator : public Integrator {
 public:
  using Integrator::Integrator;
  void attach(ForceModel& model) override;
  const BlockSparseMatrix& mass() const override { return mass_; }
  void constraints_changed(const FixedDofs&) override { kept_.forget(); }
  void save_state() override { saved_dv_ = dv_; }
  // A failed step may have left the matrix half assembled.
  void restore_state() override {
    dv_ = saved_dv_;
    kept_.forget();
  }

 protected:
  BlockSparseMatrix mass_;    // M in the model's pattern
  // Changes with mass_ (unique across integrators): a float32 system keeps its image of
  // s M under this number (SinglePrecisionSymmetric::start_assembly).
  std::uint64_t mass_version_ = 0;
  BlockSparseMatrix system_;  // A, reassembled every step
  Nodes force_, y_;           // forces; a second point (linearisation point, Newton trial)
  Vec rhs_, dv_, work_, saved_dv_;
  KeptSystem kept_;  // whether the linearised step may keep its matrix
  AggregateRotations kept_turn_;  // each body part's turn since the kept matrix was assembled
  std::vector<int> body_parts_;   // connected part of each node (of the attached model)
  int num_body_parts_ = 0;
  std::vector<Eigen::Quaterniond> part_turns_;  // kept_turn_'s rotations as quaternions
  // The kept float32 matrix without contacts, saved where an assembling step had them (its
  // values then hold them too: the next kept step starts again from this image).
  std::vector<float> kept_image_;
  bool kept_image_valid_ = false;
  bool kept_has_contacts_ = false;  // the float32 values hold the last step's contact terms
  bool kept_lower_blocks_ = false;  // the kept double matrix has its lower blocks
};

}  // namespace corotate
