#include "corotate/simulation.hpp"

#include <sstream>

#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"

namespace corotate {

Simulation::Simulation(std::unique_ptr<ForceModel> model, const IntegratorSettings& settings,
                       std::unique_ptr<LinearSolver> solver)
    : model_(std::move(model)), solver_(std::move(solver)) {
  if (!model_) throw InvalidInput("Simulation needs a force model");
  if (!solver_) solver_ = std::make_unique<PCG>();
  integrator_ = make_integrator(settings);
  integrator_->attach(*model_);
  solver_->set_geometry(model_->rest_positions());
  x_ = model_->rest_positions();
  const Index n = model_->num_nodes();
  v_.setZero(3, n);
  a_.setZero(3, n);
  f_ext_.setZero(3, n);
  load_.setZero(3, n);
  x_next_.setZero(3, n);
  v_next_.setZero(3, n);
  fixed_ = FixedDofs(model_->pattern(), std::vector<char>(3 * n, 0));
  rebuild_gravity_forces();
}

StepInput Simulation::input() { return {*model_, x_, v_, load_, fixed_, *solver_}; }

void Simulation::rebuild_gravity_forces() {
  // Consistent body-force load: M (1 (x) g). With a lumped mass it is m_i g per node.
  const Index n = num_nodes();
  Nodes g(3, n);
  g.colwise() = gravity_;
  gravity_forces_.resize(3, n);
  Vec out(3 * n);
  integrator_->mass().multiply(as_dofs(g), out);
  as_dofs(gravity_forces_) = out;
}

void Simulation::set_gravity(const Vec3& g) {
  if (!g.allFinite()) throw InvalidInput("gravity must be finite");
  gravity_ = g;
  rebuild_gravity_forces();
}

void Simulation::set_fixed_nodes(const std::vector<Index>& nodes) {
  const Index n = num_nodes();
  std::vector<char> flags(3 * n, 0);
  for (Index i : nodes) {
    if (i < 0 || i >= n) {
      std::ostringstream msg;
      msg << "node index " << i << " is out of range [0, " << n << ")";
      throw InvalidInput(msg.str());
    }
    flags[3 * i] = flags[3 * i + 1] = flags[3 * i + 2] = 1;
  }
  fixed_ = FixedDofs(model_->pattern(), flags);
  fixed_nodes_ = nodes;
  integrator_->constraints_changed(fixed_);
  solver_->reset();  // a cached factorization belongs to the old constraints
}

void Simulation::set_settings(const IntegratorSettings& settings) {
  auto integrator = make_integrator(settings);  // validates before anything changes
  integrator->attach(*model_);
  integrator->constraints_changed(fixed_);
  integrator_ = std::move(integrator);
  solver_->reset();
  rebuild_gravity_forces();
}

void Simulation::set_solver(std::unique_ptr<LinearSolver> solver) {
  if (!solver) throw InvalidInput("Simulation needs a linear solver");
  solver->set_geometry(model_->rest_positions());
  solver_ = std::move(solver);
}

void Simulation::record_estimates() {
  if (ExplicitIntegrator* e = integrator_->as_explicit()) {
    const auto [ms, count] = e->take_estimate_cost();
    stats_.estimate_ms += ms;
    stats_.estimates += count;
  }
}

void Simulation::step(int n) {
  if (n < 0) throw InvalidInput("step count must be non-negative");
  check_finite_state(x_, v_, f_ext_);
  x_backup_ = x_;  // restored if any of the n steps fails (no allocation after the first call)
  v_backup_ = v_;
  a_backup_ = a_;
  const double time_before = time_;
  const SimulationStats stats_before = stats_;
  integrator_->save_state();
  model_->save_caches();
  try {
    load_ = f_ext_ + gravity_forces_;
    const StepInput in = input();
    integrator_->begin(in);
    for (int s = 0; s < n; ++s) {
      StepStats st = integrator_->step(in, x_next_, v_next_);
      if (Index i = first_non_finite_node(x_next_); i >= 0 || !v_next_.allFinite()) {
        std::ostringstream msg;
        msg << "step " << stats_.steps + 1 << " produced non-finite positions or velocities"
            << (i >= 0 ? " (first at node " + std::to_string(i) + ")" : "") << "; the state was restored. "
            << integrator_->non_finite_hint(st);
        throw SolverFailure(msg.str());
      }
      // Copy, not swap: NumPy views point at x_'s and v_'s buffers and must stay valid.
      x_ = x_next_;
      a_ = (v_next_ - v_) / st.dt;
      v_ = v_next_;
      time_ += st.dt;
      ++stats_.steps;
      stats_.substeps += st.substeps;
      stats_.total_iterations += st.solve.iterations;
      stats_.simulated_time += st.dt;
      stats_.wall_ms += st.total_ms;
      stats_.last = std::move(st);
      record_estimates();
    }
  } catch (...) {
    x_ = x_backup_;
    v_ = v_backup_;
    a_ = a_backup_;
    time_ = time_before;
    stats_ = stats_before;
    integrator_->restore_state();
    model_->restore_caches();
    throw;
  }
}

StaticResult Simulation::solve_static(const StaticSettings& settings, const Nodes* prescribed) {
  check_finite_state(x_, v_, f_ext_);
  x_backup_ = x_;
  model_->save_caches();
  load_ = f_ext_ + gravity_forces_;
  DirectSolver direct;
  try {
    StaticResult result = corotate::solve_static(*model_, x_, load_, fixed_, settings, direct, prescribed);
    v_.setZero();
    return result;
  } catch (...) {
    x_ = x_backup_;
    model_->restore_caches();
    throw;
  }
}

ExplicitIntegrator& Simulation::explicit_integrator() {
  ExplicitIntegrator* e = integrator_->as_explicit();
  if (!e)
    throw InvalidInput(std::string("the '") + integrator_->name() +
                       "' integrator is implicit: it has no explicit stability limit");
  return *e;
}

const StabilityEstimate& Simulation::stability() {
  ExplicitIntegrator& e = explicit_integrator();
  const StabilityEstimate& est = e.stability(input());
  record_estimates();
  return est;
}

StabilityEstimate Simulation::estimate_stability(bool bound) {
  ExplicitIntegrator& e = explicit_integrator();
  const StabilityEstimate est = e.estimate_stability(input(), bound);
  record_estimates();
  return est;
}

double Simulation::kinetic_energy() const {
  Vec mv(v_.size());
  integrator_->mass().multiply(as_dofs(v_), mv);
  return 0.5 * as_dofs(v_).dot(mv);
}

}  // namespace corotate
