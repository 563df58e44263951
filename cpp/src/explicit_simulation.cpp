#include "corotate/explicit_simulation.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace corotate {

namespace {
using clock_type = std::chrono::steady_clock;
double ms_since(clock_type::time_point t0) {
  return std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
}
}  // namespace

TimeStepPolicy time_step_policy_from_name(const std::string& name) {
  if (name == "fixed") return TimeStepPolicy::Fixed;
  if (name == "online") return TimeStepPolicy::Online;
  throw InvalidInput("unknown time-step policy '" + name + "' (choose 'fixed' or 'online')");
}

OnUnstable on_unstable_from_name(const std::string& name) {
  if (name == "substep") return OnUnstable::Substep;
  if (name == "raise") return OnUnstable::Raise;
  if (name == "allow") return OnUnstable::Allow;
  throw InvalidInput("unknown on_unstable '" + name + "' (choose 'substep', 'raise' or 'allow')");
}

void ExplicitSettings::validate() const {
  if (!(time_step >= 0) || !std::isfinite(time_step))
    throw InvalidInput("time step dt must be positive and finite (or None for the stable step), got " + std::to_string(time_step));
  if (!(safety > 0 && safety <= 1)) throw InvalidInput("safety factor must be in (0, 1], got " + std::to_string(safety));
  if (!(mass_damping >= 0) || !std::isfinite(mass_damping))
    throw InvalidInput("mass damping must be >= 0 and finite, got " + std::to_string(mass_damping));
}

ExplicitSimulation::ExplicitSimulation(std::unique_ptr<ForceModel> model, const ExplicitSettings& settings)
    : model_(std::move(model)), settings_(settings), integrator_(*model_) {
  masses_ = model_->lumped_masses();
  for (Index i = 0; i < masses_.size(); ++i)
    if (!(masses_[i] > 0))
      throw InvalidInput("node " + std::to_string(i) + " has lumped mass " + std::to_string(masses_[i]) +
                         ": explicit steps need a positive mass at every node");
  settings_.validate();
  const Index n = model_->num_nodes();
  x_ = model_->rest_positions();
  v_.setZero(3, n);
  f_ext_.setZero(3, n);
  load_.setZero(3, n);
  gravity_forces_.setZero(3, n);
  work_ = model_->pattern();
  // Shortest distance between coupled nodes at rest (springs, element edges).
  double shortest = std::numeric_limits<double>::infinity();
  const auto& start = work_.row_start();
  const auto& cols = work_.columns();
  for (Index i = 0; i < n; ++i)
    for (int k = start[i]; k < start[i + 1]; ++k)
      if (cols[k] != i) {
        const double d = (x_.col(i) - x_.col(cols[k])).norm();
        if (d > 0) shortest = std::min(shortest, d);
      }
  online_tolerance_ = std::isfinite(shortest) ? 0.05 * shortest : 0.0;
  rebuild_node_factors();
}

void ExplicitSimulation::rebuild_node_factors() {
  const Index n = num_nodes();
  const Vec& m = masses_;
  inv_mass_ = m.cwiseInverse();
  damping_rate_ = Vec::Constant(n, settings_.mass_damping);
  for (Index i : fixed_nodes_) inv_mass_[i] = damping_rate_[i] = 0.0;
  inv_sqrt_mass_.resize(3 * n);
  for (Index i = 0; i < n; ++i) inv_sqrt_mass_.segment<3>(3 * i).setConstant(std::sqrt(inv_mass_[i]));
  stability_stale_ = true;
}

void ExplicitSimulation::set_gravity(const Vec3& g) {
  if (!g.allFinite()) throw InvalidInput("gravity must be finite");
  gravity_ = g;
  for (Index i = 0; i < num_nodes(); ++i) gravity_forces_.col(i) = masses_[i] * g;
}

void ExplicitSimulation::set_fixed_nodes(const std::vector<Index>& nodes) {
  const Index n = num_nodes();
  for (Index i : nodes)
    if (i < 0 || i >= n) {
      std::ostringstream msg;
      msg << "node index " << i << " is out of range [0, " << n << ")";
      throw InvalidInput(msg.str());
    }
  fixed_nodes_ = nodes;
  rebuild_node_factors();
}

void ExplicitSimulation::set_settings(const ExplicitSettings& settings) {
  settings.validate();
  settings_ = settings;
  rebuild_node_factors();
}

StabilityEstimate ExplicitSimulation::estimate_stability(bool bound) {
  const auto t0 = clock_type::now();
  StabilityEstimate est;
  est.bound = bound;
  work_.set_zero();
  if (!bound || !model_->add_stiffness_bound(1.0, work_)) {
    est.bound = false;  // no configuration-independent bound: the linearised system here
    work_.set_zero();
    model_->update(x_);
    model_->add_stiffness(1.0, work_);
  }
  est.stiffness = largest_eigenvalue(work_, inv_sqrt_mass_);
  if (model_->has_damping()) {
    work_.set_zero();
    if (!bound || !model_->add_damping_bound(1.0, work_)) {
      work_.set_zero();
      model_->update(x_);
      model_->add_damping_matrix(1.0, work_);
    }
    est.damping = largest_eigenvalue(work_, inv_sqrt_mass_);
  }
  const double omega_sq = std::max(est.stiffness.value, 0.0);
  est.omega_max = std::sqrt(omega_sq);
  est.damping_rate = std::max(est.damping.value, 0.0) + settings_.mass_damping;
  est.critical_step = critical_time_step(omega_sq, est.damping_rate);
  stats_.estimate_ms += ms_since(t0);
  ++stats_.estimates;
  return est;
}

const StabilityEstimate& ExplicitSimulation::stability() {
  const bool online = settings_.policy == TimeStepPolicy::Online;
  if (online && !stability_stale_) {
    double moved = 0;  // largest node movement since the last estimate (no allocation)
    for (Index i = 0; i < num_nodes(); ++i) moved = std::max(moved, (x_.col(i) - x_at_estimate_.col(i)).squaredNorm());
    stability_stale_ = std::sqrt(moved) > online_tolerance_;
  }
  if (stability_stale_) {
    stability_ = estimate_stability(!online);
    stability_stale_ = false;
    if (online) x_at_estimate_ = x_;
  }
  return stability_;
}

void ExplicitSimulation::check_finite_state() const { corotate::check_finite_state(x_, v_, f_ext_); }

void ExplicitSimulation::step(int n) {
  if (n < 0) throw InvalidInput("step count must be non-negative");
  check_finite_state();
  x_backup_ = x_;  // restored if any of the n steps fails (no allocation after the first call)
  v_backup_ = v_;
  const double time_before = time_;
  const ExplicitStats stats_before = stats_;
  try {
    const auto t0 = clock_type::now();
    load_ = f_ext_ + gravity_forces_;
    // The acceleration is evaluated afresh at every call: positions, loads or pins may have
    // been changed since the last one.
    integrator_.begin(settings_.scheme, x_, v_, load_, inv_mass_, damping_rate_);
    for (int s = 0; s < n; ++s) {
      const StabilityEstimate& est = stability();
      const double stable = settings_.safety * est.critical_step;
      double dt = settings_.time_step;
      int substeps = 1;
      if (dt == 0) {
        if (!std::isfinite(stable))
          throw InvalidInput("the system has no finite stable time step (no spring moves a free node); give dt explicitly");
        dt = stable;
      } else if (dt > stable * (1 + 1e-12)) {
        if (settings_.on_unstable == OnUnstable::Raise) {
          std::ostringstream msg;
          msg << "time step dt = " << dt << " s exceeds the stable step " << stable << " s (" << settings_.safety
              << " x the critical step " << est.critical_step << " s = 2/omega_max with omega_max = " << est.omega_max
              << " rad/s" << (est.damping_rate > 0 ? ", reduced for damping" : "")
              << "); use dt <= " << stable << " or on_unstable='substep'";
          throw InvalidInput(msg.str());
        }
        if (settings_.on_unstable == OnUnstable::Substep) {
          const double ratio = std::ceil(dt / stable - 1e-12);
          if (ratio > 1e9) throw InvalidInput("time step dt = " + std::to_string(dt) + " s needs more than 1e9 substeps");
          substeps = static_cast<int>(ratio);
        }
      }
      const double h = dt / substeps;
      for (int k = 0; k < substeps; ++k) integrator_.substep(x_, v_, h);
      if (Index i = first_non_finite_node(x_); i >= 0 || !v_.allFinite()) {
        std::ostringstream msg;
        msg << "step " << stats_.steps + 1 << " (substep size " << h << " s, critical step " << est.critical_step
            << " s) produced non-finite positions or velocities"
            << (i >= 0 ? " (first at node " + std::to_string(i) + ")" : "")
            << "; the state was restored. The time step is above the stability limit or a spring collapsed to zero length";
        throw SolverFailure(msg.str());
      }
      time_ += dt;
      ++stats_.steps;
      stats_.substeps += substeps;
      stats_.last_substeps = substeps;
      stats_.last_substep = h;
      stats_.simulated_time += dt;
    }
    stats_.wall_ms += ms_since(t0);
  } catch (...) {
    x_ = x_backup_;
    v_ = v_backup_;
    time_ = time_before;
    stats_ = stats_before;
    throw;
  }
}

double ExplicitSimulation::kinetic_energy() const {
  double e = 0;
  for (Index i = 0; i < num_nodes(); ++i) e += 0.5 * masses_[i] * v_.col(i).squaredNorm();
  return e;
}

}  // namespace corotate
