// What the explicit integrators share ("symplectic_euler", "verlet"; one file each in
// src/integrators/): the lumped mass, the stable time step and sub-stepping.
//
// With a(x, v) = M^-1 (f(x, v) + f_ext + M g) - alpha v  (f: elastic plus the model's own
// damping forces; alpha: mass damping; a = 0 on fixed DOFs):
//   symplectic Euler (semi-implicit Euler, see the explainer in the seeds):
//       v <- v + h a(x, v),   x <- x + h v
//   velocity Verlet (kick-drift-kick; one force evaluation per step, a is kept):
//       v_half = v + h/2 a,   x <- x + h v_half,   a <- a(x, v_half),   v <- v_half + h/2 a
// Without damping both are the leapfrog scheme: symplectic, energy error bounded for
// h < 2 / w_max (see critical_time_step.hpp). Damping forces use the lagged velocity.
//
// Time step. Each step of dt is split into as many equal substeps of at most safety x
// dt_crit as needed (on_unstable = Substep), or refused with an error naming dt and the limit
// (Raise), or taken as given (Allow: for experiments). dt = 0 means "the stable step".
// dt_crit (critical_time_step.hpp) uses w^2 = lambda_max(M^-1 K) from
//   - Fixed policy (conservative, the default): for models with a configuration-independent
//     bound of K (mass-spring: K <= L_k (x) I) that bound, estimated once (again when nodes
//     are released from the fixed set; fixing more keeps it), safe in every configuration;
//     for models without one (hyperelastic solids) the linearised system of the
//     configuration the estimate first sees, kept.
//   - Online policy: the linearised system at the current positions, re-estimated at the
//     start of a step whenever some node has moved more than 5 % of the shortest distance
//     between coupled nodes at rest since the last estimate.
// Attachment springs (fem/attachments.hpp) add k I on their nodes' diagonal blocks, so by
// Weyl's inequality lambda_max(M^-1 (K + K_a)) <= lambda_max(M^-1 K) + max k / m: that bound
// is added to the body's estimate at every step, and attaching or detaching needs no new
// eigenvalue estimate. A stiff spring on a light node shrinks the stable step accordingly.
#pragma once

#include "corotate/integrators/critical_time_step.hpp"
#include "corotate/integrators/integrator.hpp"

namespace corotate {

struct StabilityEstimate {
  EigenEstimate stiffness;  // of M^-1 K (or of its bound)
  EigenEstimate damping;    // of M^-1 C (or of its bound); zero without model damping
  double attachment_rate = 0;  // max k / m of the attachment springs [1/s^2], added to the stiffness estimate
  double omega_max = 0;     // sqrt of (stiffness estimate + attachment rate) [rad/s]
  double damping_rate = 0;  // c = damping estimate + mass damping [1/s]
  double critical_step = 0; // dt_crit [s]
  bool bound = false;       // from the configuration-independent bound (Fixed policy)
};

class ExplicitIntegrator : public Integrator {
 public:
  using Integrator::Integrator;
  void attach(ForceModel& model) override;
  const BlockSparseMatrix& mass() const override { return mass_; }
  void constraints_changed(const FixedDofs& fixed) override;
  StepStats step(const StepInput& in, Nodes& x_new, Nodes& v_new) override;
  void save_state() override;
  void restore_state() override;
  ExplicitIntegrator* as_explicit() override { return this; }
  std::string non_finite_hint(const StepStats& st) const override;

  // The estimate the next step uses (computed now, at in.x, if stale).
  const StabilityEstimate& stability(const StepInput& in);
  // A fresh estimate of the configuration-independent bound or of the linearised system at
  // in.x; does not change what the steps use.
  StabilityEstimate estimate_stability(const StepInput& in, bool bound);
  // Time spent in and number of estimates since the last call (for the statistics).
  std::pair<double, int> take_estimate_cost();

 protected:
  // One substep of size h, in place.
  virtual void substep(const StepInput& in, Nodes& x, Nodes& v, double h) = 0;
  // a = M^-1 (f(x, v) + load) - alpha v on free DOFs, 0 on fixed ones.
  void acceleration(const StepInput& in, const Nodes& x, const Nodes& v, Nodes& a);
  // omega_max, damping rate and critical step of est from its estimates and the attachments.
  void complete(StabilityEstimate& est, const Attachments& attachments) const;

 private:
  ForceModel* model_ = nullptr;
  Vec masses_, inv_mass_, inv_sqrt_mass_;  // per node, per node, per DOF (0 on fixed DOFs)
  BlockSparseMatrix mass_, work_;          // lumped M; K or C (or their bounds) for estimates
  struct Estimate {
    StabilityEstimate value;
    bool stale = true;
    Nodes x_at;  // positions of the last online estimate
  } estimate_, saved_estimate_;
  double online_tolerance_ = 0;  // node movement that triggers a new online estimate
  double estimate_ms_ = 0;
  int estimates_ = 0;
};

}  // namespace corotate
