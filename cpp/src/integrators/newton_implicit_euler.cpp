// The Newton implicit Euler step (see implicit_integrator.hpp): the incremental potential
// minimised by Newton iterations with a backtracking line search.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "corotate/integrators/implicit_integrator.hpp"
#include "corotate/solvers/lu_solver.hpp"

namespace corotate {

namespace {

// sqrt of the sum of the squared diagonal entries.
double diagonal_norm(const BlockSparseMatrix& A) {
  double sum = 0;
  for (Index i = 0; i < A.num_nodes(); ++i) sum += A.block(A.diagonal_block(i)).diagonal().squaredNorm();
  return std::sqrt(sum);
}

class NewtonImplicitEuler final : public ImplicitIntegrator {
 public:
  using ImplicitIntegrator::ImplicitIntegrator;

  void attach(ForceModel& model) override {
    ImplicitIntegrator::attach(model);
    target_.setZero(3, model.num_nodes());
    x_.setZero(3, model.num_nodes());
    lu_.reset();
  }

  StepStats step(const StepInput& in, Nodes& x_new, Nodes& v_new) override;

 private:
  // Phi(y) (see implicit_integrator.hpp).
  double incremental_potential(const StepInput& in, const Nodes& y);
  // -gradient of Phi at y into rhs_ (free DOFs), and the Hessian with the stiffness kind
  // into system_ (unprojected) when kind is not None.
  void gradient_and_hessian(const StepInput& in, const Nodes& y, StiffnessKind kind);

  Nodes target_;  // x_n + dt v_n
  Nodes x_;       // the current iterate
  LuSolver lu_;   // for a non-symmetric tangent (co-rotated hexes)
};

double NewtonImplicitEuler::incremental_potential(const StepInput& in, const Nodes& y) {
  const double dt = settings().time_step;
  double phi = in.model.energy(y) + in.attachments.energy(y) - as_dofs(in.load).dot(as_dofs(y));
  if (in.has_contacts()) phi += in.contacts->energy(y);
  rhs_ = as_dofs(y) - as_dofs(target_);
  mass_.multiply(rhs_, work_);
  phi += 0.5 / (dt * dt) * rhs_.dot(work_);
  if (settings().mass_damping != 0) {
    rhs_ = as_dofs(y) - as_dofs(in.x);
    mass_.multiply(rhs_, work_);
    phi += 0.5 * settings().mass_damping / dt * rhs_.dot(work_);
  }
  return phi;
}

void NewtonImplicitEuler::gradient_and_hessian(const StepInput& in, const Nodes& y, StiffnessKind kind) {
  const double dt = settings().time_step, alpha = settings().mass_damping;
  // -g = f(y) + f_ext - M (y - target)/dt^2 - alpha M (y - x_n)/dt, kept in force_.
  force_ = in.load;
  system_.assign_scaled(1 / (dt * dt) + alpha / dt, mass_);
  Request what;
  what.forces = true;
  what.stiffness = kind;
  Results out;
  out.forces = &force_;
  out.stiffness = &system_;
  in.model.evaluate(y, what, out);
  in.attachments.add_forces(y, force_);
  if (kind != StiffnessKind::None) in.attachments.add_stiffness(1.0, system_);
  if (in.has_contacts()) {
    in.contacts->add_forces(y, force_);
    if (kind != StiffnessKind::None) in.contacts->add_stiffness(y, 1.0, system_);
  }
  rhs_ = as_dofs(y) - as_dofs(target_);
  mass_.multiply(rhs_, work_);
  as_dofs(force_) -= work_ / (dt * dt);
  if (alpha != 0) {
    rhs_ = as_dofs(y) - as_dofs(in.x);
    mass_.multiply(rhs_, work_);
    as_dofs(force_) -= (alpha / dt) * work_;
  }
  rhs_ = as_dofs(force_);
  in.fixed.project(rhs_);
}

StepStats NewtonImplicitEuler::step(const StepInput& in, Nodes& x_new, Nodes& v_new) {
  using clock = std::chrono::steady_clock;
  const auto t_start = clock::now();
  StepStats stats;
  const double dt = settings().time_step;
  stats.dt = dt;

  // Every contact takes part: its potential's max(0, .) is the active set (contacts that
  // detection left for the linearised step's active set to take in hold no force here
  // until their node comes near).
  if (in.has_contacts()) in.contacts->activate_all();
  // Start from the inertial prediction x_n + dt v_n; fixed DOFs stay there (they keep v).
  target_ = in.x + dt * in.v;
  x_ = target_;
  // Scale of the gradient for the tolerance: the loads (the attachment springs' pull
  // included: it loads the body as an external force does), the momentum per step and the
  // elastic forces at the start of the step, whichever is largest.
  mass_.multiply(as_dofs(in.v), work_);
  force_ = in.load;
  in.attachments.add_forces(in.x, force_);
  if (in.has_contacts()) in.contacts->add_forces(in.x, force_);
  Vec reference = as_dofs(force_);
  in.fixed.project(reference);
  in.fixed.project(work_);
  double scale = reference.norm() + work_.norm() / dt;
  force_.setZero();
  {
    Request what;  // forces at the start, with what the run-away checks use
    what.forces = true;
    what.energy = in.diagnose;
    what.count_inverted = in.diagnose;
    Results out;
    out.forces = &force_;
    in.model.evaluate(in.x, what, out);
    if (in.diagnose) {
      stats.start_energy = out.energy;
      stats.start_inverted = out.inverted;
    }
  }
  reference = as_dofs(force_);
  in.fixed.project(reference);
  scale = std::max({scale, reference.norm(), 1e-300});
  // Fixed nodes that move (a hub turned by a motor) load the free ones as an external force
  // does: a beam spun up from rest has neither load, momentum nor stress on its free DOFs at
  // the start, and a tolerance relative to those asked for round-off. The load is the change
  // of the free DOFs' elastic force when the fixed DOFs alone move by dt v.
  const auto& fixed = in.fixed.list();
  if (std::any_of(fixed.begin(), fixed.end(), [&](Index d) { return as_dofs(in.v)[d] != 0; })) {
    y_ = in.x;
    for (Index d : fixed) as_dofs(y_)[d] += dt * as_dofs(in.v)[d];
    force_.setZero();
    Request what;
    what.forces = true;
    Results out;
    out.forces = &force_;
    in.model.evaluate(y_, what, out);
    work_ = as_dofs(force_);
    in.fixed.project(work_);
    scale = std::max(scale, (work_ - reference).norm());
  }

  double phi = incremental_potential(in, x_);
  double previous_g_norm = std::numeric_limits<double>::infinity();
  for (int it = 0;; ++it) {
    gradient_and_hessian(in, x_, StiffnessKind::Tangent);  // exact where the model has it
    const double g_norm = rhs_.norm();
    if (!std::isfinite(g_norm)) throw SolverFailure("Newton step: the gradient became non-finite");
    stats.newton_residuals.push_back(g_norm / scale);
    if (g_norm <= settings().newton_tolerance * scale) break;
    // The gradient cannot fall below the round-off of the forces at these coordinates, about
    // eps |x| |diag H| (every coordinate moved by one ulp): a hub spun up from rest turns a
    // 10 m beam by 1e-13 m in its first step, and a stiff beam's forces carry E times the
    // coordinates' round-off. Where the gradient stalls (falls by less than half in an
    // iteration) within 1024 times that (the estimate is rough: stalls were seen at 30-80
    // times it), the step is converged as far as it can be. Quadratic convergence never
    // stalls, so it goes on to the tolerance.
    const double round_off =
        1024 * std::numeric_limits<double>::epsilon() * as_dofs(x_).lpNorm<Eigen::Infinity>() * diagonal_norm(system_);
    if (g_norm <= round_off && g_norm > 0.5 * previous_g_norm) break;
    previous_g_norm = g_norm;
    if (it == settings().newton_iterations) {
      std::ostringstream msg;
      msg << "Newton step did not converge in " << settings().newton_iterations
          << " iterations; relative gradient norms:";
      for (double r : stats.newton_residuals) msg << ' ' << r;
      msg << " (a smaller time step, or more iterations, may help)";
      throw SolverFailure(msg.str());
    }
    in.fixed.project(system_);
    dv_.setZero();  // the Newton increment; no warm start across iterations
    in.solver.set_positions(x_);
    SolveStats solve;
    bool solved = false;
    // Contacts between parts of the body (or at points of several nodes) couple nodes outside
    // the pattern: the solver adds them, and so does the LU of a non-symmetric tangent.
    const SystemCoupling* coupled = in.has_contacts() && in.contacts->has_coupling() ? in.contacts : nullptr;
    const DiagonalTerms* terms = in.has_contacts() ? &in.contacts->diagonal_terms() : nullptr;
    const CouplingScope coupling(in.solver, coupled, terms);
    const CouplingScope lu_coupling(lu_, coupled, terms);
    try {
      // A non-symmetric tangent (ForceModel::symmetric_tangent) by sparse LU, else the
      // step's solver.
      solve = in.model.symmetric_tangent() ? in.solver.solve(system_, rhs_, dv_) : lu_.solve(system_, rhs_, dv_);
      solved = true;
    } catch (const NotPositiveDefinite&) {
    } catch (const SolverFailure&) {
      if (in.model.symmetric_tangent()) throw;  // only a singular LU falls back
    }
    if (!solved) {
      // An indefinite (or singular) exact tangent: the model's positive semi-definite stiffness.
      gradient_and_hessian(in, x_, StiffnessKind::Model);
      in.fixed.project(system_);
      dv_.setZero();
      solve = in.solver.solve(system_, rhs_, dv_);
    }
    stats.solve.iterations += solve.iterations;
    stats.solve.relative_residual = solve.relative_residual;
    stats.solve.converged = solve.converged;
    in.fixed.project(dv_);

    // Backtracking line search on Phi (Armijo, sufficient decrease 1e-4). Near the solution
    // the decrease a step promises falls below the round-off of Phi itself; a slack of
    // 1e-12 |Phi| lets those last, quadratically converging steps through.
    // A model whose forces are not the gradient of its energy (a non-symmetric tangent:
    // co-rotated hexes) has no Phi to descend on; the merit is then |g|^2, for which the
    // exact Newton direction is a descent direction (d/dt |g(x + t dx)|^2 = -2 |g|^2 at t = 0):
    // Armijo on it with the same constant.
    const bool potential = in.model.symmetric_tangent();
    const double slope = -rhs_.dot(dv_);  // g . dx
    const double slack = 1e-12 * std::abs(phi);
    double step = 1.0, phi_trial = phi;
    for (int ls = 0; ls < 30; ++ls, step *= 0.5) {
      as_dofs(y_) = as_dofs(x_) + step * dv_;
      if (!potential) {
        gradient_and_hessian(in, y_, StiffnessKind::None);  // rhs_ is recomputed at x_ next
        phi_trial = rhs_.squaredNorm();
        if (std::isfinite(phi_trial) && phi_trial <= (1 - 2e-4 * step) * g_norm * g_norm) break;
        continue;
      }
      phi_trial = incremental_potential(in, y_);
      if (std::isfinite(phi_trial) && (slope >= 0 || phi_trial <= phi + 1e-4 * step * slope + slack)) break;
    }
    if (!std::isfinite(phi_trial)) throw SolverFailure("Newton step: no finite point along the Newton direction");
    x_ = y_;
    phi = phi_trial;
    ++stats.newton_iterations;
  }
  x_new = x_;
  as_dofs(v_new) = (as_dofs(x_new) - as_dofs(in.x)) / dt;
  for (Index d : in.fixed.list()) as_dofs(v_new)[d] = as_dofs(in.v)[d];  // exactly, not (x + dt v - x) / dt
  stats.total_ms = std::chrono::duration<double, std::milli>(clock::now() - t_start).count();
  stats.solve_ms = stats.total_ms;
  return stats;
}

}  // namespace

std::unique_ptr<Integrator> make_newton_implicit_euler(const IntegratorSettings& settings) {
  return std::make_unique<NewtonImplicitEuler>(settings);
}

}  // namespace corotate
