// A body stepped explicitly (a mass-spring system, or any force model with a lumped mass):
// state, loads, pinned nodes, the stable time step and sub-stepping. What corotate.ExplicitSimulation drives frame by frame; the benchmark
// drives it directly.
//
// Time step. The user asks for steps of dt (a frame, say); each is split into as many equal
// substeps of at most safety x dt_crit as needed (on_unstable = Substep), or refused with
// an error naming dt and the limit (Raise), or taken as given (Allow: for experiments).
// dt = 0 means "the stable step": one substep of safety x dt_crit per step.
// dt_crit comes from critical_time_step.hpp, with w^2 = lambda_max(M^-1 K) from
//   - Fixed policy (conservative, the default): for models with a configuration-independent
//     bound of K (mass-spring: K <= L_k (x) I, see mass_spring.hpp) that bound, estimated once
//     (again when the pinned set changes), safe for every configuration the springs can
//     reach; for models without one (hyperelastic solids) the linearised system of the
//     configuration the estimate first sees, kept fixed.
//   - Online policy: the linearised system at the current positions, re-estimated at the
//     start of a step whenever some node has moved more than 5 % of the shortest distance
//     between coupled nodes at rest (a spring's, an element edge's) since the last estimate (the spring Hessians, and with them w, change
//     little below that); larger steps, one Lanczos run (up to 80 matrix-vector products)
//     per re-estimate.
// A step that produces non-finite positions or velocities throws SolverFailure and the
// state of before the call is restored; it never returns NaN.
#pragma once

#include <memory>
#include <vector>

#include "corotate/integrators/critical_time_step.hpp"
#include "corotate/integrators/explicit_integrator.hpp"

namespace corotate {

enum class TimeStepPolicy { Fixed, Online };
enum class OnUnstable { Substep, Raise, Allow };
TimeStepPolicy time_step_policy_from_name(const std::string& name);  // "fixed", "online"
OnUnstable on_unstable_from_name(const std::string& name);            // "substep", "raise", "allow"

struct ExplicitSettings {
  double time_step = 0;  // dt [s] per step; 0 = the stable step
  ExplicitScheme scheme = ExplicitScheme::VelocityVerlet;
  TimeStepPolicy policy = TimeStepPolicy::Fixed;
  OnUnstable on_unstable = OnUnstable::Substep;
  double safety = 0.9;        // fraction of dt_crit a substep may use, in (0, 1]
  double mass_damping = 0.0;  // alpha [1/s]: extra force -alpha m v on every free node
  void validate() const;      // throws InvalidInput naming the parameter
};

struct StabilityEstimate {
  EigenEstimate stiffness;  // of M^-1 K (or of its bound)
  EigenEstimate damping;    // of M^-1 C (or of its bound); zero without spring damping
  double omega_max = 0;     // sqrt of the stiffness estimate [rad/s]
  double damping_rate = 0;  // c = damping estimate + mass damping [1/s]
  double critical_step = 0; // dt_crit [s]
  bool bound = false;       // from the configuration-independent bound (Fixed policy)
};

struct ExplicitStats {
  long long steps = 0, substeps = 0;
  int last_substeps = 0;        // substeps of the most recent step
  double last_substep = 0;      // their size [s]
  double simulated_time = 0;    // [s]
  double wall_ms = 0;           // stepping time, estimates included [ms]
  double estimate_ms = 0;       // time spent estimating dt_crit [ms]
  long long estimates = 0;
  double ms_per_step() const { return steps ? wall_ms / steps : 0.0; }
  double real_time_ratio() const { return wall_ms > 0 ? simulated_time / (wall_ms * 1e-3) : 0.0; }
};

class ExplicitSimulation {
 public:
  ExplicitSimulation(std::unique_ptr<ForceModel> model, const ExplicitSettings& settings);

  ForceModel& model() { return *model_; }
  Index num_nodes() const { return model_->num_nodes(); }

  // State and loads, 3 x n (NumPy sees (n, 3)); callers may write into them between steps.
  Nodes& positions() { return x_; }
  Nodes& velocities() { return v_; }
  Nodes& external_forces() { return f_ext_; }
  double time() const { return time_; }

  void set_gravity(const Vec3& g);
  const Vec3& gravity() const { return gravity_; }
  // Pin the listed nodes (replacing the previous set); they keep their velocity and move with it.
  void set_fixed_nodes(const std::vector<Index>& nodes);
  const std::vector<Index>& fixed_nodes() const { return fixed_nodes_; }
  void set_settings(const ExplicitSettings& settings);
  const ExplicitSettings& settings() const { return settings_; }

  // The estimate the next step uses (computed now if stale: Fixed policy after a change of
  // the pinned set; Online policy when the configuration moved, see above).
  const StabilityEstimate& stability();
  // A fresh estimate: of the configuration-independent bound, or of the linearised system
  // at the current positions. Does not change what the steps use.
  StabilityEstimate estimate_stability(bool bound);

  // Take n steps of settings().time_step (sub-stepped as needed). On failure throws and leaves
  // positions, velocities, time and stats exactly as they were before the call.
  void step(int n = 1);

  double kinetic_energy() const;
  const ExplicitStats& stats() const { return stats_; }
  void reset_stats() { stats_ = {}; }

 private:
  void check_finite_state() const;
  void rebuild_node_factors();

  std::unique_ptr<ForceModel> model_;
  Vec masses_;  // lumped, per node
  ExplicitSettings settings_;
  ExplicitIntegrator integrator_;
  Nodes x_, v_, f_ext_, gravity_forces_, load_, x_backup_, v_backup_;
  Vec inv_mass_, damping_rate_, inv_sqrt_mass_;  // per node, per node, per DOF; 0 on pinned nodes
  BlockSparseMatrix work_;                        // K or C (or their bounds) for the estimate
  Vec3 gravity_ = Vec3::Zero();
  std::vector<Index> fixed_nodes_;
  StabilityEstimate stability_;
  bool stability_stale_ = true;
  Nodes x_at_estimate_;          // positions of the last online estimate
  double online_tolerance_ = 0;  // node movement that triggers a new online estimate
  double time_ = 0;
  ExplicitStats stats_;
};

}  // namespace corotate
