#include "corotate/simulation.hpp"

#include <chrono>
#include <sstream>

#include "corotate/solvers/direct_solver.hpp"

namespace corotate {

Simulation::Simulation(std::unique_ptr<ForceModel> model, const ImplicitEulerSettings& settings,
                       std::unique_ptr<LinearSolver> solver)
    : model_(std::move(model)), solver_(std::move(solver)) {
  if (!model_) throw InvalidInput("Simulation needs a force model");
  if (!solver_) throw InvalidInput("Simulation needs a linear solver");
  integrator_ = std::make_unique<ImplicitEuler>(*model_, settings);
  solver_->set_geometry(model_->rest_positions());
  x_ = model_->rest_positions();
  const Index n = model_->num_nodes();
  v_.setZero(3, n);
  f_ext_.setZero(3, n);
  load_.setZero(3, n);
  x_next_.setZero(3, n);
  v_next_.setZero(3, n);
  fixed_ = FixedDofs(model_->pattern(), std::vector<char>(3 * n, 0));
  rebuild_gravity_forces();
}

void Simulation::rebuild_gravity_forces() {
  // Consistent body-force load: M (1 (x) g). With a lumped mass it is m_i g per node.
  const Index n = num_nodes();
  Nodes g(3, n);
  g.colwise() = gravity_;
  gravity_forces_.resize(3, n);
  Vec out(3 * n);
  integrator_->mass().multiply(as_dofs(g), out);
  as_dofs(gravity_forces_) = out;
}

void Simulation::set_gravity(const Vec3& g) {
  if (!g.allFinite()) throw InvalidInput("gravity must be finite");
  gravity_ = g;
  rebuild_gravity_forces();
}

void Simulation::set_fixed_nodes(const std::vector<Index>& nodes) {
  const Index n = num_nodes();
  std::vector<char> flags(3 * n, 0);
  for (Index i : nodes) {
    if (i < 0 || i >= n) {
      std::ostringstream msg;
      msg << "node index " << i << " is out of range [0, " << n << ")";
      throw InvalidInput(msg.str());
    }
    flags[3 * i] = flags[3 * i + 1] = flags[3 * i + 2] = 1;
  }
  fixed_ = FixedDofs(model_->pattern(), flags);
  fixed_nodes_ = nodes;
  solver_->reset();  // a cached factorization belongs to the old constraints
}

void Simulation::set_settings(const ImplicitEulerSettings& settings) {
  integrator_ = std::make_unique<ImplicitEuler>(*model_, settings);
  solver_->reset();
  rebuild_gravity_forces();
}

void Simulation::set_solver(std::unique_ptr<LinearSolver> solver) {
  if (!solver) throw InvalidInput("Simulation needs a linear solver");
  solver_ = std::move(solver);
  solver_->set_geometry(model_->rest_positions());
}

void Simulation::check_finite_state() const { corotate::check_finite_state(x_, v_, f_ext_); }

void Simulation::step(int n) {
  if (n < 0) throw InvalidInput("step count must be non-negative");
  check_finite_state();
  x_backup_ = x_;  // restored if any of the n steps fails (no allocation after the first call)
  v_backup_ = v_;
  const double time_before = time_;
  const SimulationStats stats_before = stats_;
  const double dt = integrator_->settings().time_step;
  try {
    for (int s = 0; s < n; ++s) {
      load_ = f_ext_ + gravity_forces_;
      const StepStats st = integrator_->step(x_, v_, load_, fixed_, *solver_, x_next_, v_next_);
      if (Index i = first_non_finite_node(x_next_); i >= 0 || !v_next_.allFinite()) {
        std::ostringstream msg;
        msg << "step " << stats_.steps + 1 << " produced non-finite positions or velocities"
            << (i >= 0 ? " (first at node " + std::to_string(i) + ")" : "")
            << "; the state was restored. Is the time step too large or the mesh inverted?";
        throw SolverFailure(msg.str());
      }
      // Copy, not swap: NumPy views point at x_'s and v_'s buffers and must stay valid.
      x_ = x_next_;
      v_ = v_next_;
      time_ += dt;
      stats_.last = st;
      ++stats_.steps;
      stats_.total_iterations += st.solve.iterations;
      stats_.simulated_time += dt;
      stats_.wall_ms += st.total_ms;
    }
  } catch (...) {
    x_ = x_backup_;
    v_ = v_backup_;
    time_ = time_before;
    stats_ = stats_before;
    integrator_->reset_warm_start();
    throw;
  }
}

StaticResult Simulation::solve_static(const StaticSettings& settings, const Nodes* prescribed) {
  check_finite_state();
  const Nodes x_before = x_;
  load_ = f_ext_ + gravity_forces_;
  DirectSolver direct;
  try {
    StaticResult result = corotate::solve_static(*model_, x_, load_, fixed_, settings, direct, prescribed);
    v_.setZero();
    integrator_->reset_warm_start();
    return result;
  } catch (...) {
    x_ = x_before;
    throw;
  }
}

}  // namespace corotate
