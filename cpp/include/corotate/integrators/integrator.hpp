// The integrator seam: Simulation owns the state and calls an Integrator to advance it.
// Four integrators, each in its own file under src/integrators/ and registered in
// integrator.cpp: "linearized" and "newton" implicit Euler (implicit_integrator.hpp),
// "symplectic_euler" and "verlet" (explicit_integrator.hpp).
//
// Fixed DOFs mean the same for all of them: a step does not change their velocity, so they
// keep the velocity they have (zero unless set) and move with it; writing positions and
// velocities between steps prescribes their motion.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "corotate/contact/contact_set.hpp"
#include "corotate/fem/attachments.hpp"
#include "corotate/fem/fixed_dofs.hpp"
#include "corotate/models/force_model.hpp"
#include "corotate/solvers/linear_solver.hpp"

namespace corotate {

enum class IntegratorKind { Linearized, Newton, SymplecticEuler, Verlet };
enum class TimeStepPolicy { Fixed, Online };
enum class OnUnstable { Substep, Raise, Allow };

// Settings of every integrator; each reads what applies to it.
struct IntegratorSettings {
  IntegratorKind kind = IntegratorKind::Linearized;
  double time_step = 0.01;         // dt [s]; explicit integrators: 0 = the stable step
  double mass_damping = 0.0;       // alpha [1/s]: damping force -alpha M v (Rayleigh alpha)
  double stiffness_damping = 0.0;  // beta [s]: damping force -beta K v (Rayleigh beta); linearized only
  bool lumped_mass = false;        // implicit integrators (explicit ones always lump)
  int newton_iterations = 20;      // newton: iterations per step at most
  double newton_tolerance = 1e-6;  // newton: relative gradient norm at which it stops
  TimeStepPolicy policy = TimeStepPolicy::Fixed;   // explicit: how dt_crit is estimated
  OnUnstable on_unstable = OnUnstable::Substep;    // explicit: what a dt above the stable step does
  double safety = 0.9;             // explicit: fraction of dt_crit a substep may use, in (0, 1]
  // linearized: the system matrix is kept while no element has turned more than this angle
  // [rad] since it was assembled (kept_system.hpp), at most 0.5; 0: assembled at every step.
  double matrix_reuse_angle = 0.03;
  // Throws InvalidInput naming the parameter.
  void validate() const;
};

const std::vector<std::string>& integrator_names();  // "linearized", "newton", "symplectic_euler", "verlet"
IntegratorKind integrator_from_name(const std::string& name);
const char* integrator_name(IntegratorKind kind);
bool is_explicit(IntegratorKind kind);
const std::vector<std::string>& time_step_policy_names();  // "fixed", "online"
TimeStepPolicy time_step_policy_from_name(const std::string& name);
const char* time_step_policy_name(TimeStepPolicy policy);
const std::vector<std::string>& on_unstable_names();  // "substep", "raise", "allow"
OnUnstable on_unstable_from_name(const std::string& name);
const char* on_unstable_name(OnUnstable mode);

// What one step sees: the model, the state at its start, the loads, the fixed DOFs, the
// attachment springs (part of the elastic forces and stiffness for every integrator) and the
// linear solver (implicit integrators).
struct StepInput {
  ForceModel& model;
  const Nodes& x;     // 3 x n positions
  const Nodes& v;     // 3 x n velocities
  const Nodes& load;  // 3 x n external forces, gravity included
  const FixedDofs& fixed;
  const Attachments& attachments;
  LinearSolver& solver;
  bool diagnose = true;  // compute what the loud-failure checks need (start energy, inversions)
  // The step's contacts (implicit integrators; null or empty: none), detected at x: their
  // potential joins the body's like the attachment springs' (contact/contact_set.hpp).
  ContactSet* contacts = nullptr;
  bool has_contacts() const { return contacts && !contacts->empty(); }
};

struct StepStats {
  double dt = 0;                         // simulated time the step advanced [s]
  SolveStats solve;                      // of the last linear solve (iterations: summed over Newton)
  int newton_iterations = 0;             // 0 for the linearised step
  int contact_passes = 0;                // linearised step: solves after the first (contacts released)
  bool kept_matrix = false;              // linearised step: kept an earlier step's matrix (kept_system.hpp)
  std::vector<double> newton_residuals;  // relative gradient norm before each Newton iteration
  int substeps = 1;                      // explicit: substeps taken, and their size [s]
  double substep = 0;
  double assembly_ms = 0, solve_ms = 0, estimate_ms = 0, total_ms = 0;
  int estimates = 0;                     // explicit: stability estimates made in this step
  // What the step's own evaluation found at its start state x (implicit integrators; the
  // simulation's loud-failure checks use them): elastic energy (NaN when not evaluated) and
  // the number of inverted elements.
  double start_energy = std::numeric_limits<double>::quiet_NaN();
  Index start_inverted = 0;
  // Set by Simulation: the loud failures of this step (see simulation.hpp).
  bool solver_stalled = false, energy_growth = false;
};

class ExplicitIntegrator;

class Integrator {
 public:
  explicit Integrator(const IntegratorSettings& settings) : settings_(settings) { settings.validate(); }
  virtual ~Integrator() = default;
  const IntegratorSettings& settings() const { return settings_; }
  const char* name() const { return integrator_name(settings_.kind); }

  // Called once with the model it will step (mass matrix, work buffers).
  virtual void attach(ForceModel& model) = 0;
  // The mass matrix the integrator uses, in the model's pattern (gravity loads are M g).
  virtual const BlockSparseMatrix& mass() const = 0;
  // The fixed set changed.
  virtual void constraints_changed(const FixedDofs&) {}
  // Called at the start of every Simulation::step(n) call: the user may have written into
  // positions, velocities or loads since the last step.
  virtual void begin(const StepInput&) {}
  // Advance in.x, in.v by one step into x_new, v_new (3 x n each), leaving everything the
  // caller sees untouched, so the result can be checked before it is committed.
  virtual StepStats step(const StepInput& in, Nodes& x_new, Nodes& v_new) = 0;
  // State that carries from step to step (warm starts, stability estimates): saved before a
  // Simulation::step call and restored when it fails, so a failed call changes nothing.
  virtual void save_state() {}
  virtual void restore_state() {}
  // What to tell a user whose step st produced non-finite values.
  virtual std::string non_finite_hint(const StepStats&) const {
    return "Is the time step too large or the mesh inverted?";
  }
  // The explicit integrators' stability interface; nullptr for implicit ones.
  virtual ExplicitIntegrator* as_explicit() { return nullptr; }

 private:
  IntegratorSettings settings_;
};

// The integrator settings.kind names; throws InvalidInput for invalid settings.
std::unique_ptr<Integrator> make_integrator(const IntegratorSettings& settings);

}  // namespace corotate
