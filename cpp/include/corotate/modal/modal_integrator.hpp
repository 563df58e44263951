// Time stepping and statics of a reduced (modal) body with an orthonormalised basis:
// modal mass I, Rayleigh damping C = alpha I + beta K0 (K0 the modal stiffness at rest),
// internal forces f(q) from ModalForces, external modal forces p = Phi^T f_ext.
//
// One linearised backward-Euler step (the full-model step of the README, with M = I):
//     (I + dt C + dt^2 T(q)) dv = dt (f(q) + p - C v) - dt^2 T(q) v,  v += dv,  q += dt v,
// T = -df/dq. For a linear body the matrix is constant and factorised once (until dt, the
// damping or the load stiffness change); otherwise it is factorised every step, an r x r
// Cholesky (r ~ 20: about a microsecond). Steps allocate nothing.
//
// Statics: Newton iterations on f(q) + p = 0 with load stepping, the same contract as the
// full static solver (statics/static_solver.hpp).
#pragma once

#include <vector>

#include "corotate/modal/modal_forces.hpp"

namespace corotate {

struct ModalStepSettings {
  double dt = 0.01;
  double mass_damping = 0.0;       // alpha [1/s]
  double stiffness_damping = 0.0;  // beta [s]
  void validate() const;
};

class ModalIntegrator {
 public:
  using Mat = Eigen::MatrixXd;

  explicit ModalIntegrator(ModalForces forces, ModalStepSettings settings = {});

  Index size() const { return forces_.size(); }
  const ModalStepSettings& settings() const { return settings_; }
  void set_settings(const ModalStepSettings& s);
  void set_load_stiffness(const Mat& extra);  // see ModalForces; refactorises when needed
  ModalForces& forces() { return forces_; }

  // The state (writable between steps).
  Vec q, v, p;
  double time = 0.0;

  // n steps. Transactional: on bad state (non-finite q, v, p) InvalidInput, on a step that
  // turns non-finite SolverFailure; either way the state is as before the call.
  void step(int n);
  // Static equilibrium f(q) + p = 0 by Newton with load_steps equal increments of p from
  // q on entry; |residual| <= tolerance |p| per step. Returns the iteration count; throws
  // SolverFailure (state restored) when a load step does not converge. v is set to zero.
  int solve_static(int load_steps, double tolerance, int max_iterations);
  void reset();  // q = v = p = 0, t = 0

  // f(q) of the current state.
  const Vec& internal_forces();

 private:
  void single_step();
  void factor_linear_system();

  ModalForces forces_;
  ModalStepSettings settings_;
  Mat damping_, system_, tangent_;
  Eigen::LLT<Mat> llt_;
  Eigen::LDLT<Mat> ldlt_;
  bool linear_factor_valid_ = false;
  Vec f_, rhs_, dv_;
};

}  // namespace corotate
