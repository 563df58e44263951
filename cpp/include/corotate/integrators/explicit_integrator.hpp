// Explicit time integration of any force model with a lumped mass: symplectic Euler and
// velocity Verlet (mass-spring systems, and FE models such as StVK sheets).
//
// With a(x, v) = M^-1 (f(x, v) + f_ext + M g) - alpha v  (f: elastic plus the model's own
// damping forces; alpha: mass damping):
//   symplectic Euler (semi-implicit Euler, see the explainer in the seeds):
//       v <- v + h a(x, v),   x <- x + h v
//   velocity Verlet (kick-drift-kick; one force evaluation per step, a is kept):
//       v_half = v + h/2 a,   x <- x + h v_half,   a <- a(x, v_half),   v <- v_half + h/2 a
// Without damping both are the leapfrog scheme: symplectic, second-order accurate positions
// (Verlet; symplectic Euler's velocities lag by half a step), energy error bounded for
// h < 2 / w_max (see critical_time_step.hpp). Damping forces use the lagged (half-step)
// velocity, which makes the damping first-order accurate but keeps one force sweep per step.
// Pinned nodes have inverse mass 0: their velocity stays, and they move with it.
#pragma once

#include <string>

#include "corotate/models/force_model.hpp"

namespace corotate {

enum class ExplicitScheme { SymplecticEuler, VelocityVerlet };
ExplicitScheme explicit_scheme_from_name(const std::string& name);  // "symplectic_euler", "verlet"
const char* explicit_scheme_name(ExplicitScheme scheme);

class ExplicitIntegrator {
 public:
  explicit ExplicitIntegrator(ForceModel& model);

  // Prepare a run of substeps from (x, v): load = f_ext + M g (3 x n), inv_mass and
  // damping_rate per node (0 for pinned nodes). The references must outlive the run.
  // Verlet evaluates the acceleration here; the run then needs one evaluation per substep.
  void begin(ExplicitScheme scheme, const Nodes& x, const Nodes& v, const Nodes& load, const Vec& inv_mass,
             const Vec& damping_rate);
  // One step of size h, in place. No allocation.
  void substep(Nodes& x, Nodes& v, double h);

 private:
  void acceleration(const Nodes& x, const Nodes& v);  // into a_

  ForceModel& model_;
  ExplicitScheme scheme_ = ExplicitScheme::VelocityVerlet;
  const Nodes* load_ = nullptr;
  const Vec* inv_mass_ = nullptr;
  const Vec* damping_rate_ = nullptr;
  Nodes a_;
};

}  // namespace corotate
