// When a floating-frame step's iterations factor their Jacobian, and when they may stop.
//
// The step's equations are solved by a chord method: a factored Jacobian is kept over several
// iterations. Where it is evaluated matters more than how often: at the step's start guess
// (the velocities of the last step, for modes that vibrate many times a step a poor guess) a
// 20-mode body converged at a rate of 1/300 per iteration, eight iterations to 1e-14; at the
// first corrected iterate, near the solution, at 1e-3 to 1e-4. So:
//
//  * the first iteration takes the factor kept from the last step (evaluated there near its
//    solution, which is this step's start), and factors at the start guess only when there is
//    none for this step size and kind of step;
//  * the second iteration factors at its iterate, and that factor is kept for the rest of the
//    step and for the next step's first iteration; later iterations factor again only when
//    convergence slows (the residual falls by less than 4x);
//  * a kept factor that made the first correction worse is dropped and the step restarts
//    from its start guess with a fresh one;
//  * once the residual falls at a measured rate, the iterate after a correction is accepted
//    without evaluating it when rate x residual is below the tolerance (the estimate SUNDIALS'
//    nonlinear solvers stop on), which saves the last evaluation.
//
// The 20-mode tumbling link of bench/floating_frame_step.py: 8.1 evaluations and one factor
// per step before, 4.2 evaluations and one factor after.
#pragma once

namespace corotate {

class JacobianSchedule {
 public:
  enum class Next { Solve, FactorAndSolve, Restart };

  // A step of size h begins; kind tells steps with different Jacobians apart (free, held,
  // driven). Its first iteration may reuse the factor kept from the last step of the same h
  // and kind.
  void begin(double h, int kind) {
    reuse_ = kept_ && h == kept_h_ && kind == kept_kind_;
    h_ = h;
    kind_ = kind;
    evaluations_ = 0;
    last_ = rate_ = 0.0;
  }
  // After each evaluation of the residual (relative): factor or not, or restart (the caller
  // puts the iterate back to the step's start guess and evaluates it again).
  Next after_evaluation(double residual) {
    ++evaluations_;
    if (evaluations_ == 2 && reuse_ && !(residual < last_)) {  // (NaN included)
      reuse_ = kept_ = false;
      evaluations_ = 0;
      return Next::Restart;
    }
    rate_ = evaluations_ > 1 ? residual / last_ : 1.0;
    const bool factor = evaluations_ == 1 ? !reuse_ : evaluations_ == 2 || rate_ > 0.25;
    last_ = residual;
    if (factor) {
      kept_ = true;
      kept_h_ = h_;
      kept_kind_ = kind_;
    }
    return factor ? Next::FactorAndSolve : Next::Solve;
  }
  // After a correction: has it converged by the rate measured so far (two or more
  // corrections with the factor of the second iteration)?
  bool converged_by_rate(double tolerance) const { return evaluations_ >= 3 && rate_ * last_ <= tolerance; }
  // The kept factor no longer fits (the body's loads, support or stiffening changed, or a
  // step failed and left it undefined).
  void invalidate() { kept_ = false; }

 private:
  bool kept_ = false, reuse_ = false;
  double kept_h_ = 0.0, h_ = 0.0;
  int kept_kind_ = -1, kind_ = -1;
  int evaluations_ = 0;
  double last_ = 0.0, rate_ = 0.0;
};

}  // namespace corotate
