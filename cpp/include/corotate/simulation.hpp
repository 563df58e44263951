// A body being simulated: its force model, state (x, v), loads, fixed nodes, integrator
// and solver, and the statistics of its steps. This is what the Python API drives frame by
// frame; the benchmark drives it directly.
#pragma once

#include <memory>
#include <vector>

#include "corotate/integrators/implicit_euler.hpp"
#include "corotate/statics/static_solver.hpp"

namespace corotate {

struct SimulationStats {
  StepStats last;                 // the most recent step
  long long steps = 0;            // steps taken since the last reset_stats
  long long total_iterations = 0;
  double simulated_time = 0;      // seconds of simulated time in those steps
  double wall_ms = 0;             // milliseconds of wall time they took
  double ms_per_step() const { return steps ? wall_ms / steps : 0.0; }
  double iterations_per_step() const { return steps ? double(total_iterations) / steps : 0.0; }
  double real_time_ratio() const { return wall_ms > 0 ? simulated_time / (wall_ms * 1e-3) : 0.0; }
};

class Simulation {
 public:
  Simulation(std::unique_ptr<ForceModel> model, const ImplicitEulerSettings& settings,
             std::unique_ptr<LinearSolver> solver);

  ForceModel& model() { return *model_; }
  Index num_nodes() const { return model_->num_nodes(); }

  // State and loads, 3 x n (NumPy sees (n, 3)); callers may write into them between steps.
  Nodes& positions() { return x_; }
  Nodes& velocities() { return v_; }
  Nodes& external_forces() { return f_ext_; }
  double time() const { return time_; }

  void set_gravity(const Vec3& g);
  const Vec3& gravity() const { return gravity_; }
  // Fix the listed nodes in all three axes (replacing the previous set); they keep their
  // current positions and velocities, so moving them between steps prescribes motion.
  void set_fixed_nodes(const std::vector<Index>& nodes);
  const std::vector<Index>& fixed_nodes() const { return fixed_nodes_; }

  void set_settings(const ImplicitEulerSettings& settings);
  const ImplicitEulerSettings& settings() const { return integrator_->settings(); }
  void set_solver(std::unique_ptr<LinearSolver> solver);

  // Take n steps of dt. On failure (non-finite input or result, solver failure) throws and
  // leaves positions, velocities and time exactly as they were before the call.
  void step(int n = 1);

  // Static equilibrium under external forces and gravity; velocities become zero.
  // prescribed (3 x n, optional): end positions of the fixed nodes, reached in the load steps
  // (displacement control). Throws SolverFailure and restores the state when it does not
  // converge.
  StaticResult solve_static(const StaticSettings& settings, const Nodes* prescribed = nullptr);

  // Total force the body's mass feels from gravity (M * g per DOF, with the active mass).
  const Nodes& gravity_forces() const { return gravity_forces_; }
  const SimulationStats& stats() const { return stats_; }
  void reset_stats() { stats_ = {}; }

 private:
  void check_finite_state() const;
  void rebuild_gravity_forces();

  std::unique_ptr<ForceModel> model_;
  std::unique_ptr<ImplicitEuler> integrator_;
  std::unique_ptr<LinearSolver> solver_;
  Nodes x_, v_, f_ext_, gravity_forces_, load_, x_next_, v_next_, x_backup_, v_backup_;
  Vec3 gravity_ = Vec3::Zero();
  std::vector<Index> fixed_nodes_;
  FixedDofs fixed_;
  double time_ = 0;
  SimulationStats stats_;
};

}  // namespace corotate
