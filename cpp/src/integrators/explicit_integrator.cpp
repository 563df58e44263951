#include "corotate/integrators/explicit_integrator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "corotate/models/explicit_traits.hpp"

namespace corotate {

namespace {
using clock_type = std::chrono::steady_clock;
double ms_since(clock_type::time_point t0) {
  return std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
}
}  // namespace

void ExplicitIntegrator::attach(ForceModel& model) {
  model_ = &model;
  masses_ = model.lumped_masses();
  for (Index i = 0; i < masses_.size(); ++i)
    if (!(masses_[i] > 0))
      throw InvalidInput("node " + std::to_string(i) + " has lumped mass " + std::to_string(masses_[i]) +
                         ": explicit steps need a positive mass at every node");
  mass_ = model.mass_matrix(true);
  work_ = model.pattern();
  // Shortest distance between coupled nodes at rest (springs, element edges).
  const Nodes& rest = model.rest_positions();
  double shortest = std::numeric_limits<double>::infinity();
  const auto& start = work_.row_start();
  const auto& cols = work_.columns();
  for (Index i = 0; i < rest.cols(); ++i)
    for (int k = start[i]; k < start[i + 1]; ++k)
      if (cols[k] != i) {
        const double d = (rest.col(i) - rest.col(cols[k])).norm();
        if (d > 0) shortest = std::min(shortest, d);
      }
  online_tolerance_ = std::isfinite(shortest) ? 0.05 * shortest : 0.0;
  constraints_changed(FixedDofs());
}

void ExplicitIntegrator::constraints_changed(const FixedDofs& fixed) {
  const Index n = masses_.size();
  const Vec before = inv_sqrt_mass_;  // zero on the DOFs fixed until now
  inv_mass_ = masses_.cwiseInverse();
  inv_sqrt_mass_.resize(3 * n);
  for (Index i = 0; i < n; ++i) inv_sqrt_mass_.segment<3>(3 * i).setConstant(std::sqrt(inv_mass_[i]));
  fixed.project(inv_sqrt_mass_);  // fixed DOFs take no part in the eigenproblem
  // Fixing more DOFs restricts M^-1 K to fewer of them, and the largest eigenvalue of a
  // principal submatrix is no larger (Cauchy interlacing): the estimate stays safe, and a
  // grab by fixing costs no new estimate. Releasing a DOF can raise it: estimate again.
  bool released = before.size() != inv_sqrt_mass_.size();
  for (Index d = 0; d < before.size() && !released; ++d) released = before[d] == 0 && inv_sqrt_mass_[d] != 0;
  if (released) estimate_.stale = true;
}

void ExplicitIntegrator::save_state() { saved_estimate_ = estimate_; }
void ExplicitIntegrator::restore_state() { estimate_ = saved_estimate_; }

void ExplicitIntegrator::acceleration(const StepInput& in, const Nodes& x, const Nodes& v, Nodes& a) {
  a = in.load;
  if (const ExplicitTraits* traits = in.model.explicit_traits()) traits->add_forces_and_damping(x, v, a);
  else in.model.add_forces(x, a);
  in.attachments.add_forces(x, a);
  const double alpha = settings().mass_damping;
  const double* im = inv_mass_.data();
  for (Index i = 0; i < a.cols(); ++i) a.col(i) = im[i] * a.col(i) - alpha * v.col(i);
  in.fixed.project(a);
}

StabilityEstimate ExplicitIntegrator::estimate_stability(const StepInput& in, bool bound) {
  const auto t0 = clock_type::now();
  const ExplicitTraits* traits = in.model.explicit_traits();
  StabilityEstimate est;
  est.bound = bound && traits;  // models without a configuration-independent bound: the linearised system here
  work_.set_zero();
  if (est.bound) traits->add_stiffness_bound(1.0, work_);
  else in.model.add_stiffness(in.x, StiffnessKind::Model, 1.0, work_);
  est.stiffness = largest_eigenvalue(work_, inv_sqrt_mass_);
  if (traits && traits->has_damping()) {
    work_.set_zero();
    if (est.bound) traits->add_damping_bound(1.0, work_);
    else traits->add_damping_matrix(in.x, 1.0, work_);
    est.damping = largest_eigenvalue(work_, inv_sqrt_mass_);
  }
  complete(est, in.attachments);
  estimate_ms_ += ms_since(t0);
  ++estimates_;
  return est;
}

void ExplicitIntegrator::complete(StabilityEstimate& est, const Attachments& attachments) const {
  est.attachment_rate = attachments.max_rate(masses_);
  const double omega_sq = std::max(est.stiffness.value, 0.0) + est.attachment_rate;
  est.omega_max = std::sqrt(omega_sq);
  est.damping_rate = std::max(est.damping.value, 0.0) + settings().mass_damping;
  est.critical_step = critical_time_step(omega_sq, est.damping_rate);
}

const StabilityEstimate& ExplicitIntegrator::stability(const StepInput& in) {
  const bool online = settings().policy == TimeStepPolicy::Online;
  if (online && !estimate_.stale) {
    double moved = 0;  // largest node movement since the last estimate (no allocation)
    for (Index i = 0; i < in.x.cols(); ++i)
      moved = std::max(moved, (in.x.col(i) - estimate_.x_at.col(i)).squaredNorm());
    estimate_.stale = std::sqrt(moved) > online_tolerance_;
  }
  if (estimate_.stale) {
    estimate_.value = estimate_stability(in, !online);
    estimate_.stale = false;
    if (online) estimate_.x_at = in.x;
  }
  complete(estimate_.value, in.attachments);  // the springs may have changed since (cheap)
  return estimate_.value;
}

std::string ExplicitIntegrator::non_finite_hint(const StepStats& st) const {
  std::ostringstream msg;
  msg << "Substep size " << st.substep << " s, critical step " << estimate_.value.critical_step
      << " s: the time step is above the stability limit or a spring collapsed to zero length";
  return msg.str();
}

std::pair<double, int> ExplicitIntegrator::take_estimate_cost() {
  const std::pair<double, int> cost{estimate_ms_, estimates_};
  estimate_ms_ = 0;
  estimates_ = 0;
  return cost;
}

StepStats ExplicitIntegrator::step(const StepInput& in, Nodes& x_new, Nodes& v_new) {
  const auto t0 = clock_type::now();
  StepStats stats;
  const StabilityEstimate& est = stability(in);
  const double stable = settings().safety * est.critical_step;
  double dt = settings().time_step;
  int substeps = 1;
  if (dt == 0) {
    if (!std::isfinite(stable))
      throw InvalidInput("the system has no finite stable time step (no spring moves a free node); give dt explicitly");
    dt = stable;
  } else if (dt > stable * (1 + 1e-12)) {
    if (settings().on_unstable == OnUnstable::Raise) {
      std::ostringstream msg;
      msg << "time step dt = " << dt << " s exceeds the stable step " << stable << " s (" << settings().safety
          << " x the critical step " << est.critical_step << " s = 2/omega_max with omega_max = " << est.omega_max
          << " rad/s" << (est.damping_rate > 0 ? ", reduced for damping" : "") << "); use dt <= " << stable
          << " or on_unstable='substep'";
      throw InvalidInput(msg.str());
    }
    if (settings().on_unstable == OnUnstable::Substep) {
      const double ratio = std::ceil(dt / stable - 1e-12);
      if (ratio > 1e9) throw InvalidInput("time step dt = " + std::to_string(dt) + " s needs more than 1e9 substeps");
      substeps = static_cast<int>(ratio);
    }
  }
  const double h = dt / substeps;
  x_new = in.x;
  v_new = in.v;
  for (int k = 0; k < substeps; ++k) substep(in, x_new, v_new, h);
  stats.dt = dt;
  stats.substeps = substeps;
  stats.substep = h;
  stats.total_ms = ms_since(t0);
  return stats;
}

}  // namespace corotate
