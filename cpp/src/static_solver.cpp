#include "corotate/statics/static_solver.hpp"

#include <cmath>
#include <sstream>

namespace corotate {

void StaticSettings::validate() const {
  if (load_steps < 1) throw InvalidInput("static solve: load_steps must be at least 1");
  if (max_iterations < 1) throw InvalidInput("static solve: max_iterations must be at least 1");
  if (!(tolerance > 0)) throw InvalidInput("static solve: tolerance must be positive");
}

StaticResult solve_static(ForceModel& model, Nodes& x, const Nodes& load, const FixedDofs& fixed,
                          const StaticSettings& settings, LinearSolver& solver) {
  settings.validate();
  const Index n = model.num_nodes();
  Nodes residual(3, n);
  Vec r(3 * n), dx = Vec::Zero(3 * n);
  BlockSparseMatrix K = model.pattern();
  solver.reset();

  Vec free_load = as_dofs(load);
  fixed.project(free_load);
  // Reference size for the tolerance: the load, or, for pure prescribed displacement, the
  // first residual.
  double reference = free_load.norm();

  StaticResult result;
  for (int s = 1; s <= settings.load_steps; ++s) {
    const double lambda = double(s) / settings.load_steps;
    auto& history = result.residual_history.emplace_back();
    for (int it = 0;; ++it) {
      model.update(x);
      residual = lambda * load;
      K.set_zero();
      model.add_linearized_forces_and_stiffness(x, residual, 1.0, K);  // at y = x: f(x)
      r = as_dofs(residual);
      fixed.project(r);
      const double r_norm = r.norm();
      if (!std::isfinite(r_norm)) throw SolverFailure("static solve: the residual became non-finite (elements collapsed?)");
      if (reference == 0) reference = r_norm > 0 ? r_norm : 1.0;
      history.push_back(r_norm / reference);
      if (r_norm <= settings.tolerance * reference) break;
      if (it == settings.max_iterations) {
        std::ostringstream msg;
        msg << "static solve did not converge in " << settings.max_iterations << " iterations at load step " << s
            << " of " << settings.load_steps << "; relative residuals:";
        for (size_t k = 0; k < history.size(); k += std::max<size_t>(1, history.size() / 10)) msg << ' ' << history[k];
        msg << " ... " << history.back() << " (try more load steps)";
        throw SolverFailure(msg.str());
      }
      fixed.project(K);
      dx.setZero();
      solver.solve(K, r, dx);
      as_dofs(x) += dx;
      ++result.total_iterations;
    }
  }
  return result;
}

}  // namespace corotate
