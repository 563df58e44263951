// Linearised implicit (backward) Euler, one linear solve per step (Baraff & Witkin 1998).
//
// Backward Euler asks for
//     M dv = dt (f(x + dx) - C (v + dv) + f_ext),   dx = dt (v + dv).
// Linearising the elastic force at the start of the step, f(x + dx) ~ f(x) - K dx, with
// K the model's stiffness (for the co-rotational model R K_e R^T at the current rotations):
//     (M + dt C + dt^2 K) dv = dt (f(x) + f_ext - C v) - dt^2 K v.
// With Rayleigh damping C = alpha M + beta K the system matrix is a combination of M and K,
//     A = (1 + dt alpha) M + (dt^2 + dt beta) K,
// and the right-hand side is b = dt (f(x) + f_ext) - (A - M) v.
// Then v <- v + dv and x <- x + dt v (the new velocity: the step is implicit in both).
// Fixed DOFs keep dv = 0 by projection (see FixedDofs).
//
// With newton_iterations > 0 the step is instead solved to convergence: backward Euler is
// the minimiser of the incremental potential
//     Phi(x) = 1/(2 dt^2) |x - x_n - dt v_n|_M^2 + alpha/(2 dt) |x - x_n|_M^2 + E(x) - f_ext.x,
// whose gradient is M (x - x_n - dt v_n)/dt^2 + alpha M (x - x_n)/dt - f(x) - f_ext and whose
// Hessian is (1/dt^2 + alpha/dt) M + K(x). Each Newton iteration solves Hessian dx = -gradient
// and backtracks along dx until Phi decreases enough (Armijo), so the step cannot blow up
// where the linearisation is poor (large rotations, hyperelastic models near inversion).
// It stops when |gradient| <= newton_tolerance * max(|f_ext| + |M v_n| / dt, |f(x_n)|) on the
// free DOFs;
// then v = (x - x_n) / dt. Stiffness-proportional damping is not a potential and is refused.
#pragma once

#include <memory>
#include <vector>

#include "corotate/fem/fixed_dofs.hpp"
#include "corotate/models/force_model.hpp"
#include "corotate/solvers/linear_solver.hpp"

namespace corotate {

struct ImplicitEulerSettings {
  double time_step = 0.01;      // dt [s]
  double rayleigh_alpha = 0.0;  // mass-proportional damping [1/s]
  double rayleigh_beta = 0.0;   // stiffness-proportional damping [s]
  bool lumped_mass = false;     // consistent mass is the better choice for implicit steps
  int newton_iterations = 0;    // 0: linearised, one solve per step; > 0: Newton, at most this many
  double newton_tolerance = 1e-6;  // relative gradient norm at which Newton stops
  void validate() const;
};

struct StepStats {
  SolveStats solve;                 // of the last linear solve (iterations: summed over Newton)
  int newton_iterations = 0;        // 0 for the linearised step
  std::vector<double> newton_residuals;  // relative gradient norm before each Newton iteration
  double rotation_ms = 0, assembly_ms = 0, solve_ms = 0, total_ms = 0;
};

class ImplicitEuler {
 public:
  ImplicitEuler(ForceModel& model, const ImplicitEulerSettings& settings);

  const ImplicitEulerSettings& settings() const { return settings_; }
  const BlockSparseMatrix& mass() const { return mass_; }
  // The next solve starts from zero instead of the last answer (after a failed step).
  void reset_warm_start() { dv_.setZero(); }

  // Advance (x, v) by one step. f_ext: 3 x n external nodal forces (gravity included).
  // Writes the new state into x_new, v_new and leaves x, v untouched, so a caller can
  // check the result before committing it.
  StepStats step(const Nodes& x, const Nodes& v, const Nodes& f_ext, const FixedDofs& fixed, LinearSolver& solver,
                 Nodes& x_new, Nodes& v_new);

 private:
  StepStats newton_step(const Nodes& x, const Nodes& v, const Nodes& f_ext, const FixedDofs& fixed,
                        LinearSolver& solver, Nodes& x_new, Nodes& v_new);
  // Phi(y) for the Newton step (updates the model's state to y).
  double incremental_potential(const Nodes& y, const Nodes& x, const Nodes& inertia_target, const Nodes& f_ext);

  ForceModel& model_;
  ImplicitEulerSettings settings_;
  BlockSparseMatrix mass_;    // M in the model's pattern
  BlockSparseMatrix system_;  // A, reassembled every step
  Nodes force_;               // f(x) + f_ext
  Nodes y_;                   // x + (dt + beta) v
  Vec rhs_, dv_, work_;
  Nodes trial_, target_;      // Newton: line-search point, x_n + dt v_n
};

}  // namespace corotate
