#include "corotate/modal/modal_integrator.hpp"

#include <cmath>
#include <string>

namespace corotate {

void ModalStepSettings::validate() const {
  if (!(dt > 0) || !std::isfinite(dt)) throw InvalidInput("dt must be a positive finite time step");
  if (!(mass_damping >= 0) || !std::isfinite(mass_damping))
    throw InvalidInput("mass damping alpha must be finite and >= 0");
  if (!(stiffness_damping >= 0) || !std::isfinite(stiffness_damping))
    throw InvalidInput("stiffness damping beta must be finite and >= 0");
}

ModalIntegrator::ModalIntegrator(ModalForces forces, ModalStepSettings settings)
    : forces_(std::move(forces)), settings_(settings) {
  settings_.validate();
  const Index r = size();
  q = Vec::Zero(r);
  v = Vec::Zero(r);
  p = Vec::Zero(r);
  system_ = Mat::Zero(r, r);
  tangent_ = Mat::Zero(r, r);
  f_ = Vec::Zero(r);
  rhs_ = Vec::Zero(r);
  dv_ = Vec::Zero(r);
  llt_ = Eigen::LLT<Mat>(r);
  ldlt_ = Eigen::LDLT<Mat>(r);
  set_settings(settings_);
}

void ModalIntegrator::set_settings(const ModalStepSettings& s) {
  s.validate();
  settings_ = s;
  damping_ = s.stiffness_damping * forces_.base_stiffness();
  damping_.diagonal().array() += s.mass_damping;
  linear_factor_valid_ = false;
}

void ModalIntegrator::set_load_stiffness(const Mat& extra) {
  forces_.set_load_stiffness(extra);
  linear_factor_valid_ = false;
}

void ModalIntegrator::factor_linear_system() {
  const double dt = settings_.dt;
  system_ = dt * damping_ + dt * dt * forces_.stiffness();
  system_.diagonal().array() += 1.0;
  llt_.compute(system_);
  if (llt_.info() != Eigen::Success)
    throw SolverFailure("the modal step matrix I + dt C + dt^2 K is not positive definite (negative stiffness?)");
  linear_factor_valid_ = true;
}

void ModalIntegrator::single_step() {
  const double dt = settings_.dt;
  if (forces_.is_linear()) {
    if (!linear_factor_valid_) factor_linear_system();
    forces_.evaluate(q, f_, nullptr);
    tangent_ = forces_.stiffness();
  } else {
    forces_.evaluate(q, f_, &tangent_);
    system_ = dt * damping_ + dt * dt * tangent_;
    system_.diagonal().array() += 1.0;
    llt_.compute(system_);
    if (llt_.info() != Eigen::Success)
      throw SolverFailure(
          "the modal step matrix I + dt C + dt^2 T(q) is not positive definite: the tangent "
          "stiffness lost definiteness at this amplitude (take smaller steps or loads)");
  }
  rhs_.noalias() = dt * (f_ + p);
  rhs_.noalias() -= dt * damping_ * v;
  rhs_.noalias() -= dt * dt * tangent_ * v;
  dv_ = llt_.solve(rhs_);
  v += dv_;
  q.noalias() += dt * v;
  time += dt;
}

void ModalIntegrator::step(int n) {
  if (n < 0) throw InvalidInput("step count must be >= 0");
  if (q.size() != size() || v.size() != size() || p.size() != size())
    throw InvalidInput("modal state vectors must have " + std::to_string(size()) + " entries");
  if (!q.allFinite() || !v.allFinite() || !p.allFinite())
    throw InvalidInput("the modal state (coordinates, velocities or forces) is not finite");
  const Vec q0 = q, v0 = v;
  const double t0 = time;
  try {
    for (int k = 0; k < n; ++k) {
      single_step();
      if (!q.allFinite() || !v.allFinite()) throw SolverFailure("a modal step produced non-finite coordinates");
    }
  } catch (...) {
    q = q0;
    v = v0;
    time = t0;
    throw;
  }
}

int ModalIntegrator::solve_static(int load_steps, double tolerance, int max_iterations) {
  if (load_steps < 1) throw InvalidInput("load_steps must be >= 1");
  if (!(tolerance > 0)) throw InvalidInput("tolerance must be > 0");
  if (max_iterations < 1) throw InvalidInput("max_iterations must be >= 1");
  if (!q.allFinite() || !p.allFinite()) throw InvalidInput("the modal state is not finite");
  const Vec q0 = q, p_total = p;
  const double scale = std::max(p_total.norm(), 1e-300);
  int iterations = 0;
  try {
    for (int s = 1; s <= load_steps; ++s) {
      const Vec load = (double(s) / load_steps) * p_total;
      bool converged = false;
      for (int it = 0; it < max_iterations; ++it) {
        forces_.evaluate(q, f_, &tangent_);
        rhs_ = f_ + load;
        if (rhs_.norm() <= tolerance * scale) {
          converged = true;
          break;
        }
        ldlt_.compute(tangent_);
        if (ldlt_.info() != Eigen::Success) throw SolverFailure("the modal tangent stiffness is singular");
        dv_ = ldlt_.solve(rhs_);
        q += dv_;
        ++iterations;
        if (!q.allFinite()) throw SolverFailure("a modal Newton iteration produced non-finite coordinates");
      }
      if (!converged)
        throw SolverFailure("modal static solve: load step " + std::to_string(s) + " did not converge in " +
                            std::to_string(max_iterations) + " iterations");
    }
  } catch (...) {
    q = q0;
    throw;
  }
  v.setZero();
  return iterations;
}

void ModalIntegrator::reset() {
  q.setZero();
  v.setZero();
  p.setZero();
  time = 0.0;
}

const Vec& ModalIntegrator::internal_forces() {
  forces_.evaluate(q, f_, nullptr);
  return f_;
}

}  // namespace corotate
