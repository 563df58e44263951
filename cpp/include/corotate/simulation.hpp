// A body being simulated: its force model, state (x, v), loads, fixed nodes, integrator
// and linear solver, and the statistics of its steps. What the Python API drives frame by
// frame and the benchmark drives directly; implicit and explicit integration alike (the
// integrator is a setting, see integrators/integrator.hpp).
//
// Every call that changes the state is a transaction: on failure (non-finite input or
// result, solver failure, an unstable time step that is refused) it throws and leaves
// positions, velocities, time, statistics and the integrator's carried state (warm starts,
// stability estimates) exactly as they were before the call.
//
// Loud failures. A run can go wrong without producing NaN; every implicit step checks, from
// what its own evaluation computes anyway:
//   - solver_stalled: the linear solve ended at its iteration cap with a relative residual
//     of 1 or more (it did not reduce the residual at all: the step is garbage);
//   - inverted: elements inverted or flat (det F <= 0) at the state the step started from;
//   - energy_growth: the total energy (elastic + kinetic, with the lumped mass, minus the work
//     potential of the loads) rose by more than 1 % of its size above the lowest it reached
//     since anything last drove the body (loads changed, fixed nodes moving, state written).
//     Implicit Euler dissipates, so this is a run-away (too few PCG iterations, a linearised
//     step far too large).
// The last two are seen at the start of the next step (their data comes from its sweep). The
// failure policy says what happens: Warn (the default) counts them in the stats, which the
// Python layer turns into one warning per kind and run; Raise makes the step fail (state
// restored); Ignore skips the checks.
#pragma once

#include <memory>
#include <vector>

#include "corotate/integrators/explicit_integrator.hpp"
#include "corotate/solvers/linear_solver.hpp"
#include "corotate/statics/static_solver.hpp"

namespace corotate {

enum class FailurePolicy { Ignore, Warn, Raise };
const std::vector<std::string>& failure_policy_names();  // "ignore", "warn", "raise"
FailurePolicy failure_policy_from_name(const std::string& name);

// A call that reached a simulation while another thread's call (a step) holds it: RuntimeError.
struct SimulationBusy : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SimulationStats {
  StepStats last;                 // the most recent step
  long long stalled_steps = 0;    // loud failures counted (see above)
  long long inverted_steps = 0;
  long long energy_growth_steps = 0;
  long long steps = 0;            // steps taken since the last reset_stats
  long long substeps = 0;         // explicit substeps in those steps (= steps for implicit ones)
  long long total_iterations = 0; // CG iterations
  long long kept_matrix_steps = 0; // linearised steps that kept an earlier step's matrix
  long long estimates = 0;        // explicit: stability estimates
  double simulated_time = 0;      // seconds of simulated time in those steps
  double wall_ms = 0;             // milliseconds of wall time the step calls took (callbacks excluded)
  double estimate_ms = 0;         // of which stability estimates
  double ms_per_step() const { return steps ? wall_ms / steps : 0.0; }
  double iterations_per_step() const { return steps ? double(total_iterations) / steps : 0.0; }
  double real_time_ratio() const { return wall_ms > 0 ? simulated_time / (wall_ms * 1e-3) : 0.0; }
};

class Simulation {
 public:
  // solver: for implicit integrators; null = PCG with its default settings.
  Simulation(std::unique_ptr<ForceModel> model, const IntegratorSettings& settings,
             std::unique_ptr<LinearSolver> solver = nullptr);
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Claims the simulation for one call (what every mutating member does itself); throws
  // SimulationBusy naming `what` when another thread's call holds it. For callers that use
  // model() or several members as one operation (the Python bindings).
  class Claim {
   public:
    Claim(const Simulation& sim, const char* what);
    ~Claim() { busy_.store(false, std::memory_order_release); }
    Claim(const Claim&) = delete;
    Claim& operator=(const Claim&) = delete;

   private:
    std::atomic<bool>& busy_;
  };

  ForceModel& model() { return *model_; }
  Index num_nodes() const { return model_->num_nodes(); }

  // State and loads, 3 x n (NumPy sees (n, 3)); callers may write into them between steps.
  Nodes& positions() { return x_; }
  Nodes& velocities() { return v_; }
  Nodes& external_forces() { return f_ext_; }
  // (v_new - v_old) / dt of the last step (3 x n; zero before the first): with the Newton
  // integrator M a = f_int(x) + f_ext holds on the free DOFs, so on fixed ones
  // f_int + f_ext - M a is the force the body exerts on its supports.
  const Nodes& accelerations() const { return a_; }
  double time() const { return time_; }

  void set_gravity(const Vec3& g);
  const Vec3& gravity() const { return gravity_; }
  // Fix the listed nodes in all three axes (replacing the previous set). A step does not
  // change their velocity: they keep it (zero unless set) and move with it, so writing
  // positions and velocities between steps prescribes their motion. Cheap at any time: the
  // projection is found from the fixed nodes' rows only, and the linear solver keeps its
  // factorization or preconditioner hierarchy (LinearSolver::constraints_changed).
  void set_fixed_nodes(const std::vector<Index>& nodes);
  const std::vector<Index>& fixed_nodes() const { return fixed_nodes_; }

  // Attachments (fem/attachments.hpp): zero-rest-length springs of stiffness k pulling nodes
  // towards targets, part of the implicit system (stable for any k) or of the explicit forces
  // and stable step. For dragging: attach on grab, move the targets between frames, detach on
  // release; none of it rebuilds anything. targets: 3 x nodes.size(); stiffness: one per node.
  // Throws InvalidInput (nothing changed) for bad indices, targets or stiffness.
  void attach(const std::vector<Index>& nodes, const Nodes& targets, const Vec& stiffness);
  void move_attachments(const std::vector<Index>& nodes, const Nodes& targets);
  void detach(const std::vector<Index>& nodes);
  void detach_all();
  const Attachments& attachments() const { return attachments_; }

  // Contact with rigid obstacles (contact/contact_set.hpp), implicit integrators only.
  // add_obstacle: the body touches `obstacle` with Coulomb friction coefficient `friction`;
  // one obstacle may be shared by several simulations (a tool touching two bodies) and moved
  // between frames (Obstacle::set_pose): over the next step it moves from where this body
  // last saw it to where it is. Throws InvalidInput (nothing changed) for a bad friction, an
  // obstacle added twice, an explicit integrator, or contact nodes that start inside the
  // obstacle (deeper than 1e-9 of the body's size).
  void add_obstacle(std::shared_ptr<Obstacle> obstacle, double friction);
  void remove_obstacle(const Obstacle& obstacle);  // InvalidInput when it is not there
  void set_friction(const Obstacle& obstacle, double friction);
  const std::vector<ObstacleLink>& obstacles() const { return obstacle_links_; }
  // The nodes that can touch (default: all; the Python layer sets the surface's). Validated.
  // Replaces contact points.
  void set_contact_nodes(const std::vector<Index>& nodes);
  // Contact points instead of the nodes (contact/contact_set.hpp: an embedded surface's
  // vertices, each a weighted combination of an element's nodes). Throws InvalidInput (nothing
  // changed) for bad indices or weights (non-finite, not summing to 1), points that start
  // inside an obstacle, or contact between parts.
  void set_contact_points(ContactPoints points);
  void set_contact_settings(const ContactSettings& settings);
  // Contact between the body's parts (its mesh's separate pieces: several bodies simulated
  // as one): part_of_node gives each node's part (0..P-1, P >= 2), surface the outward
  // triangles of every part's closed boundary (body node indices), friction the Coulomb
  // coefficient between any two parts. Each part's contact nodes touch the others' surfaces
  // (contact/contact_set.hpp). Throws InvalidInput (nothing changed) for bad ids, a triangle
  // joining two parts, a part surface that is not closed, an explicit integrator, or a
  // contact node that starts inside another part. self_contact: each part's surface nodes
  // also touch the part's own surface (away from their neighbourhood; P = 1 allowed).
  void set_part_contact(const Triangles& surface, const std::vector<int>& part_of_node, double friction,
                        bool self_contact = false);
  void clear_part_contact();
  bool has_contact() const { return !obstacle_links_.empty() || contacts_.has_parts(); }
  // The contacts of the last step and the force each exerted on the body at its end.
  const ContactSet& contacts() const { return contacts_; }

  // A new integrator (validated first; on InvalidInput nothing changes).
  void set_settings(const IntegratorSettings& settings);
  const IntegratorSettings& settings() const { return integrator_->settings(); }
  // A new linear solver (it factorizes or builds its preconditioner afresh); the integrator's
  // warm start (the last step's answer) stays the initial guess of the next solve.
  void set_solver(std::unique_ptr<LinearSolver> solver);
  void set_failure_policy(FailurePolicy policy);
  FailurePolicy failure_policy() const { return failure_policy_; }
  const BlockSparseMatrix& mass() const { return integrator_->mass(); }

  // Take n steps of settings().time_step. after_each_step (optional) is called after every
  // step, the last included, with the number of steps done so far in this call (progress
  // reports, interruption checks); whatever it throws fails the call like any failure: the
  // state is restored to what it was before the call.
  void step(int n = 1, const std::function<void(int done)>& after_each_step = {});

  // Back to the rest state: positions = rest, velocities, accelerations and external forces
  // zero, time 0, statistics reset, the integrator's carried state (warm starts, stability
  // estimates), the solver's factorizations and the model's rotation caches cleared. The fixed
  // nodes, attachments, gravity, settings, solver kind and failure policy are kept.
  void reset();

  // Static equilibrium under external forces and gravity; velocities become zero. Refuses
  // (InvalidInput) while nodes are attached.
  // prescribed (3 x n, optional): end positions of the fixed nodes, reached in the load steps
  // (displacement control). Throws SolverFailure and restores the state when it does not
  // converge.
  // after_each_load_step: as after_each_step of step(), once per load step.
  StaticResult solve_static(const StaticSettings& settings, const Nodes* prescribed = nullptr,
                            const std::function<void(int done)>& after_each_load_step = {});

  // Explicit integrators only (InvalidInput otherwise): the stability estimate the next
  // step uses, and a fresh one of the bound or of the linearised system at the positions.
  const StabilityEstimate& stability();
  StabilityEstimate estimate_stability(bool bound);

  double kinetic_energy() const;  // 1/2 v^T M v with the integrator's mass
  // Total force the body's mass feels from gravity (M g per DOF, with the integrator's mass).
  const Nodes& gravity_forces() const { return gravity_forces_; }
  const SimulationStats& stats() const { return stats_; }
  void reset_stats();

 private:
  void rebuild_gravity_forces();
  std::unique_ptr<Integrator> make_attached_integrator(const IntegratorSettings& settings) const;
  StepInput input();
  ExplicitIntegrator& explicit_integrator();
  void record_estimates();
  // The loud-failure checks of one step (see above); marks st, counts, throws under Raise.
  void check_health(StepStats& st);
  Index obstacle_index(const Obstacle& obstacle) const;  // -1 when not added
  void ensure_contact_properties();
  // Throws InvalidInput when contact units of `set` start inside the obstacle.
  void check_outside(const Obstacle& obstacle,
                     const ContactSet& set) const;  // each node's mass, stiffness and size for ContactSet
  void detect_contacts(double dt);

  std::unique_ptr<ForceModel> model_;
  std::unique_ptr<Integrator> integrator_;
  std::unique_ptr<LinearSolver> solver_;
  Nodes x_, v_, a_, f_ext_, gravity_forces_, load_, x_next_, v_next_, x_backup_, v_backup_, a_backup_;
  Vec3 gravity_ = Vec3::Zero();
  std::vector<Index> fixed_nodes_;
  FixedDofs fixed_;
  Attachments attachments_;
  std::vector<ObstacleLink> obstacle_links_, obstacle_links_backup_;
  std::vector<Pose> obstacle_poses_;  // each obstacle's pose, read once per step() call
  ContactSet contacts_, contacts_backup_;
  double time_ = 0;
  SimulationStats stats_;
  FailurePolicy failure_policy_ = FailurePolicy::Warn;
  Vec lumped_masses_;  // per node, for the kinetic energy of the energy check
  struct EnergyBaseline {
    bool valid = false;
    double lowest = 0;                    // the lowest total energy since the body was last driven
    long long attachments_version = -1;  // the springs of the last check (moving them drives the body)
    bool touched = false;                // the last checked step had contacts (they did work in it)
  };
  struct EnergyCheck : EnergyBaseline {
    Nodes load;
    Nodes x_end, v_end;  // the state the last call left: a user who writes into it drives the body
  } energy_check_;
  // What a failed call restores: the baseline's scalars alone (x_end and v_end are written
  // only after every step of a call succeeded; a load taken over during a failed call
  // invalidates the baseline instead, which is what a changed load does anyway).
  EnergyBaseline energy_check_backup_;
  bool energy_check_took_load_ = false;
  mutable std::atomic<bool> busy_{false};  // see Claim
};

}  // namespace corotate
