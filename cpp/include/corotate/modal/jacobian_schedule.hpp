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
//  * unless the kept factor converges well enough to be cheaper: at the second iteration, the
//    corrections still needed at the rate the kept factor showed, against a factorisation
//    (kFactorCost evaluations) and those needed at the rate the last fresh factor showed; a
//    kept factor whose rate then falls 10x behind is dropped. A pendulum's Jacobian changes
//    slowly: its kept factor converges at 1e-2 per correction, 6 evaluations and rarely a
//    factor (18 us per step at 20 modes) against 3 evaluations and a factor every step (20
//    us); a tumbling body's changes fast, its kept factor falls behind and it refactors each step;
//  * a kept factor that made the first correction worse is dropped and the step restarts
//    from its start guess with a fresh one;
//  * once the residual falls at a measured rate, the iterate after a correction is accepted
//    without evaluating it when rate x residual is below the tolerance (the estimate SUNDIALS'
//    nonlinear solvers stop on), which saves the last evaluation.
//
// The 20-mode tumbling link of bench/floating_frame_step.py: 8.1 evaluations and one factor
// per step with a factor at each step's start guess, 4.2 evaluations and one factor with this.
#pragma once

#include <cmath>

namespace corotate {

class JacobianSchedule {
 public:
  enum class Next { Solve, FactorAndSolve, Restart };

  // A factorisation costs about this many evaluations of the residual (6 + r unknowns:
  // measured 3-3.5 for 20 modes).
  static constexpr double kFactorCost = 3.0;

  explicit JacobianSchedule(double tolerance) : tolerance_(tolerance) {}

  // A step of size h begins; kind tells steps with different Jacobians apart (free, held,
  // driven). Its first iteration may reuse the factor kept from the last step of the same h
  // and kind.
  void begin(double h, int kind) {
    reuse_ = kept_ && h == kept_h_ && kind == kept_kind_;
    h_ = h;
    kind_ = kind;
    evaluations_ = factored_at_ = 0;
    last_ = rate_ = step_fresh_rate_ = 0.0;
  }
  // After each evaluation of the residual (relative): factor or not, or restart (the caller
  // puts the iterate back to the step's start guess and evaluates it again).
  Next after_evaluation(double residual) {
    ++evaluations_;
    if (evaluations_ == 2 && reuse_ && !(residual < last_)) {  // (NaN included)
      reuse_ = kept_ = false;
      evaluations_ = factored_at_ = 0;
      return Next::Restart;
    }
    rate_ = evaluations_ > 1 ? residual / last_ : 1.0;
    if (factored_at_ > 0 && evaluations_ == factored_at_ + 1) fresh_rate_ = step_fresh_rate_ = rate_;
    // Later, a kept factor whose rate falls 10x behind what justified keeping it (its rate at
    // the second evaluation) is dropped too.
    const bool kept_fell_behind = evaluations_ > 2 && factored_at_ == 0 && rate_ > 10.0 * kept_rate_;
    bool factor = evaluations_ == 1 ? !reuse_ : rate_ > 0.25 || kept_fell_behind;
    if (evaluations_ == 2 && !factor) {
      factor = !reuse_ || corrections(residual, rate_) > kFactorCost + corrections(residual, fresh_rate_);
      kept_rate_ = rate_;
    }
    last_ = residual;
    if (factor) {
      kept_ = true;
      kept_h_ = h_;
      kept_kind_ = kind_;
      factored_at_ = evaluations_;
    }
    return factor ? Next::FactorAndSolve : Next::Solve;
  }
  // After a correction: has it converged by the rate measured so far (two or more
  // corrections with the factor of the second iteration)?
  bool converged_by_rate() const { return evaluations_ >= 3 && rate_ * last_ <= tolerance_; }
  // The residual's reduction by the first correction with a factor made in this step (0 when
  // none was): a Jacobian that is right gives about the residual itself (Newton), a wrong or
  // incomplete one a constant rate (what tests look at).
  double fresh_rate() const { return step_fresh_rate_; }
  // The kept factor no longer fits (the body's loads, support or stiffening changed, or a
  // step failed and left it undefined).
  void invalidate() { kept_ = false; }

 private:
  // Corrections from `residual` to the tolerance at `rate` per correction (many when the
  // rate is not below 1).
  double corrections(double residual, double rate) const {
    if (!(rate < 1.0) || !(rate > 0.0)) return 1e9;
    return residual <= tolerance_ ? 0.0 : std::ceil(std::log(tolerance_ / residual) / std::log(rate));
  }

  double tolerance_;
  int factored_at_ = 0;       // the evaluation this step factored at (0: none yet)
  double fresh_rate_ = 1e-3;  // the rate the last fresh factor gave, one correction after it
  double kept_rate_ = 1.0;    // the kept factor's first rate in this step
  double step_fresh_rate_ = 0.0;
  bool kept_ = false, reuse_ = false;
  double kept_h_ = 0.0, h_ = 0.0;
  int kept_kind_ = -1, kind_ = -1;
  int evaluations_ = 0;
  double last_ = 0.0, rate_ = 0.0;
};

}  // namespace corotate
