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
#pragma once

#include <memory>

#include "corotate/fem/fixed_dofs.hpp"
#include "corotate/models/force_model.hpp"
#include "corotate/solvers/linear_solver.hpp"

namespace corotate {

struct ImplicitEulerSettings {
  double time_step = 0.01;      // dt [s]
  double rayleigh_alpha = 0.0;  // mass-proportional damping [1/s]
  double rayleigh_beta = 0.0;   // stiffness-proportional damping [s]
  bool lumped_mass = false;     // consistent mass is the better choice for implicit steps
  void validate() const;
};

struct StepStats {
  SolveStats solve;
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
  ForceModel& model_;
  ImplicitEulerSettings settings_;
  BlockSparseMatrix mass_;    // M in the model's pattern
  BlockSparseMatrix system_;  // A, reassembled every step
  Nodes force_;               // f(x) + f_ext
  Nodes y_;                   // x + (dt + beta) v
  Vec rhs_, dv_, work_;
};

}  // namespace corotate
