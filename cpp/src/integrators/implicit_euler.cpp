#include "corotate/integrators/implicit_euler.hpp"

#include <chrono>
#include <cmath>

namespace corotate {

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

void ImplicitEulerSettings::validate() const {
  if (!(time_step > 0) || !std::isfinite(time_step)) throw InvalidInput("time step must be positive and finite, got dt = " + std::to_string(time_step));
  if (!(rayleigh_alpha >= 0) || !std::isfinite(rayleigh_alpha)) throw InvalidInput("Rayleigh alpha must be >= 0");
  if (!(rayleigh_beta >= 0) || !std::isfinite(rayleigh_beta)) throw InvalidInput("Rayleigh beta must be >= 0");
  if (newton_iterations < 0) throw InvalidInput("newton_iterations must be >= 0 (0: linearised step)");
  if (newton_iterations > 0 && rayleigh_beta != 0)
    throw InvalidInput("stiffness-proportional (Rayleigh beta) damping is not a potential: the Newton step supports "
                       "mass-proportional damping (alpha) only");
  if (newton_iterations > 0 && !(newton_tolerance > 0)) throw InvalidInput("newton_tolerance must be positive");
}

ImplicitEuler::ImplicitEuler(ForceModel& model, const ImplicitEulerSettings& settings)
    : model_(model), settings_(settings) {
  settings.validate();
  mass_ = model.mass_matrix(settings.lumped_mass);
  system_ = model.pattern();
  const Index n = model.num_nodes();
  force_.resize(3, n);
  y_.resize(3, n);
  trial_.resize(3, n);
  target_.resize(3, n);
  rhs_.setZero(3 * n);
  dv_.setZero(3 * n);
  work_.setZero(3 * n);
}

StepStats ImplicitEuler::step(const Nodes& x, const Nodes& v, const Nodes& f_ext, const FixedDofs& fixed,
                              LinearSolver& solver, Nodes& x_new, Nodes& v_new) {
  if (settings_.newton_iterations > 0) return newton_step(x, v, f_ext, fixed, solver, x_new, v_new);
  using clock = std::chrono::steady_clock;
  StepStats stats;
  const auto t_start = clock::now();
  const double dt = settings_.time_step;
  const double mass_coef = 1 + dt * settings_.rayleigh_alpha;
  const double stiffness_coef = dt * dt + dt * settings_.rayleigh_beta;

  model_.update(x);
  stats.rotation_ms = ms_since(t_start);

  const auto t_assembly = clock::now();
  // b = dt (f(x) - (dt + beta) K v + f_ext) - dt alpha M v, where the first two terms are
  // the linearised force at y = x + (dt + beta) v: no matrix-vector product needed.
  force_ = f_ext;
  y_ = x + (dt + settings_.rayleigh_beta) * v;
  system_.assign_scaled(mass_coef, mass_);
  model_.add_linearized_forces_and_stiffness(y_, force_, stiffness_coef, system_);
  rhs_ = dt * as_dofs(force_);
  if (settings_.rayleigh_alpha != 0) {
    mass_.multiply(as_dofs(v), work_);
    rhs_ -= (dt * settings_.rayleigh_alpha) * work_;
  }
  fixed.project(system_);
  fixed.project(rhs_);
  stats.assembly_ms = ms_since(t_assembly);

  // dv_ still holds the previous step's answer: the warm start.
  const auto t_solve = clock::now();
  stats.solve = solver.solve(system_, rhs_, dv_);
  fixed.project(dv_);
  stats.solve_ms = ms_since(t_solve);

  as_dofs(v_new) = as_dofs(v) + dv_;
  as_dofs(x_new) = as_dofs(x) + dt * as_dofs(v_new);
  stats.total_ms = ms_since(t_start);
  return stats;
}

}  // namespace corotate
