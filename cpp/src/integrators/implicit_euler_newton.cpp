// The Newton variant of the implicit Euler step (see integrators/implicit_euler.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "corotate/integrators/implicit_euler.hpp"

namespace corotate {

double ImplicitEuler::incremental_potential(const Nodes& y, const Nodes& x, const Nodes& inertia_target,
                                            const Nodes& f_ext) {
  const double dt = settings_.time_step;
  model_.update(y);
  double phi = model_.energy(y) - as_dofs(f_ext).dot(as_dofs(y));
  rhs_ = as_dofs(y) - as_dofs(inertia_target);
  mass_.multiply(rhs_, work_);
  phi += 0.5 / (dt * dt) * rhs_.dot(work_);
  if (settings_.rayleigh_alpha != 0) {
    rhs_ = as_dofs(y) - as_dofs(x);
    mass_.multiply(rhs_, work_);
    phi += 0.5 * settings_.rayleigh_alpha / dt * rhs_.dot(work_);
  }
  return phi;
}

StepStats ImplicitEuler::newton_step(const Nodes& x, const Nodes& v, const Nodes& f_ext, const FixedDofs& fixed,
                                     LinearSolver& solver, Nodes& x_new, Nodes& v_new) {
  using clock = std::chrono::steady_clock;
  const auto t_start = clock::now();
  StepStats stats;
  const double dt = settings_.time_step, alpha = settings_.rayleigh_alpha;
  const double mass_coef = 1 / (dt * dt) + alpha / dt;

  // Start from the inertial prediction x_n + dt v_n; fixed DOFs stay there (they keep v).
  target_ = x + dt * v;
  x_new = target_;
  // Scale of the gradient for the tolerance: the loads, the momentum per step and the
  // elastic forces at the start of the step, whichever is largest.
  mass_.multiply(as_dofs(v), work_);
  Vec reference = as_dofs(f_ext);
  fixed.project(reference);
  fixed.project(work_);
  double scale = reference.norm() + work_.norm() / dt;
  model_.update(x);
  force_.setZero();
  model_.add_forces(x, force_);
  reference = as_dofs(force_);
  fixed.project(reference);
  scale = std::max({scale, reference.norm(), 1e-300});

  double phi = incremental_potential(x_new, x, target_, f_ext);  // also updates the model at x_new
  for (int it = 0;; ++it) {
    // gradient g = M (x - target)/dt^2 + alpha M (x - x_n)/dt - f(x) - f_ext, kept in force_ as -g
    force_ = f_ext;
    system_.assign_scaled(mass_coef, mass_);
    model_.add_forces(x_new, force_);
    model_.add_tangent_stiffness(x_new, 1.0, system_);  // exact where the model has it
    rhs_ = as_dofs(x_new) - as_dofs(target_);
    mass_.multiply(rhs_, work_);
    as_dofs(force_) -= work_ / (dt * dt);
    if (alpha != 0) {
      rhs_ = as_dofs(x_new) - as_dofs(x);
      mass_.multiply(rhs_, work_);
      as_dofs(force_) -= (alpha / dt) * work_;
    }
    rhs_ = as_dofs(force_);  // -g
    fixed.project(rhs_);
    const double g_norm = rhs_.norm();
    if (!std::isfinite(g_norm)) throw SolverFailure("Newton step: the gradient became non-finite");
    stats.newton_residuals.push_back(g_norm / scale);
    if (g_norm <= settings_.newton_tolerance * scale) break;
    if (it == settings_.newton_iterations) {
      std::ostringstream msg;
      msg << "Newton step did not converge in " << settings_.newton_iterations << " iterations; relative gradient norms:";
      for (double r : stats.newton_residuals) msg << ' ' << r;
      msg << " (a smaller time step, or more iterations, may help)";
      throw SolverFailure(msg.str());
    }
    fixed.project(system_);
    dv_.setZero();  // the Newton increment; no warm start across iterations
    SolveStats solve;
    try {
      solve = solver.solve(system_, rhs_, dv_);
    } catch (const SolverFailure&) {
      // An indefinite exact tangent: fall back to the model's positive semi-definite stiffness.
      system_.assign_scaled(mass_coef, mass_);
      model_.add_stiffness(1.0, system_);
      fixed.project(system_);
      dv_.setZero();
      solve = solver.solve(system_, rhs_, dv_);
    }
    stats.solve.iterations += solve.iterations;
    stats.solve.relative_residual = solve.relative_residual;
    stats.solve.converged = solve.converged;
    fixed.project(dv_);

    // Backtracking line search on Phi (Armijo, sufficient decrease 1e-4). Near the solution
    // the decrease a step promises falls below the round-off of Phi itself; a slack of
    // 1e-12 |Phi| lets those last, quadratically converging steps through.
    const double slope = -rhs_.dot(dv_);  // g . dx
    const double slack = 1e-12 * std::abs(phi);
    double step = 1.0, phi_trial = phi;
    for (int ls = 0; ls < 30; ++ls, step *= 0.5) {
      as_dofs(trial_) = as_dofs(x_new) + step * dv_;
      phi_trial = incremental_potential(trial_, x, target_, f_ext);
      if (std::isfinite(phi_trial) && (slope >= 0 || phi_trial <= phi + 1e-4 * step * slope + slack)) break;
    }
    if (!std::isfinite(phi_trial)) throw SolverFailure("Newton step: no finite point along the Newton direction");
    x_new = trial_;  // the model's state is already at trial_ (set by incremental_potential)
    phi = phi_trial;
    ++stats.newton_iterations;
  }
  as_dofs(v_new) = (as_dofs(x_new) - as_dofs(x)) / dt;
  stats.total_ms = std::chrono::duration<double, std::milli>(clock::now() - t_start).count();
  stats.solve_ms = stats.total_ms;
  return stats;
}

}  // namespace corotate
