#include "corotate/statics/static_solver.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "corotate/solvers/lu_solver.hpp"

namespace corotate {

void StaticSettings::validate() const {
  if (load_steps < 1) throw InvalidInput("static solve: load_steps must be at least 1");
  if (max_iterations < 1) throw InvalidInput("static solve: max_iterations must be at least 1");
  if (!(tolerance > 0)) throw InvalidInput("static solve: tolerance must be positive");
}

StaticResult solve_static(ForceModel& model, Nodes& x, const Nodes& load, const FixedDofs& fixed,
                          const StaticSettings& settings, LinearSolver& solver, const Nodes* prescribed,
                          const std::function<void(int done)>& after_each_load_step) {
  settings.validate();
  const Index n = model.num_nodes();
  if (prescribed && (prescribed->cols() != n || !prescribed->allFinite()))
    throw InvalidInput("static solve: prescribed positions must be finite, one column per node");
  Nodes residual(3, n), trial(3, n);
  Vec r(3 * n), dx = Vec::Zero(3 * n);
  BlockSparseMatrix K = model.pattern();
  solver.reset();
  // A non-symmetric exact tangent (co-rotated hexes) is solved by sparse LU; `solver` (which
  // may assume symmetry) then only solves the fallback systems of the Model stiffness.
  LuSolver lu;
  LinearSolver& tangent_solver = model.symmetric_tangent() ? solver : lu;
  const Nodes start = x;  // fixed DOFs move from here to the prescribed positions

  // r(y) = f_int(y) + lambda * load on the free DOFs.
  // With a stiffness, also K(y) of the given kind into it.
  auto evaluate = [&](const Nodes& y, double lambda, StiffnessKind kind) {
    residual = lambda * load;
    Request what;
    what.forces = true;
    what.stiffness = kind;
    Results out;
    out.forces = &residual;
    if (kind != StiffnessKind::None) {
      K.set_zero();
      out.stiffness = &K;
    }
    model.evaluate(y, what, out);
    r = as_dofs(residual);
    fixed.project(r);
    return r.norm();
  };

  Vec free_load = as_dofs(load);
  fixed.project(free_load);
  // Reference size for the tolerance: the load, or, under pure displacement control, the
  // first residual scaled to the whole displacement.
  double reference = free_load.norm();

  StaticResult result;
  for (int s = 1; s <= settings.load_steps; ++s) {
    const double lambda = double(s) / settings.load_steps;
    if (prescribed)
      for (Index d : fixed.list())
        as_dofs(x)[d] = as_dofs(start)[d] + lambda * (as_dofs(*prescribed)[d] - as_dofs(start)[d]);
    auto& history = result.residual_history.emplace_back();
    for (int it = 0;; ++it) {
      const double r_norm = evaluate(x, lambda, StiffnessKind::Tangent);  // exact where the model has it
      if (!std::isfinite(r_norm))
        throw SolverFailure("static solve: the residual became non-finite (elements collapsed?)");
      if (reference == 0) reference = r_norm > 0 ? r_norm * settings.load_steps : 1.0;
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
      const Vec rhs = r;
      dx.setZero();
      solver.set_positions(x);
      bool solved = false;
      try {
        tangent_solver.solve(K, rhs, dx);
        solved = true;
      } catch (const NotPositiveDefinite&) {
      } catch (const SolverFailure&) {
        if (&tangent_solver == &solver) throw;  // only a singular LU falls back
      }
      if (!solved) {
        // The exact tangent can be indefinite (or singular) far from equilibrium (compressed
        // or strongly rotated elements); the model's positive semi-definite stiffness still
        // points the way.
        K.set_zero();
        model.add_stiffness(x, StiffnessKind::Model, 1.0, K);
        fixed.project(K);
        dx.setZero();
        solver.solve(K, rhs, dx);
      }
      // Guard against blow-up: the residual may rise for an iteration and still converge, so
      // only a step that makes it non-finite or ten times larger is halved (a strict descent
      // rule on |r| stalls those iterations). The first iteration of a load step is exempt
      // from the factor ten: it is the tangent predictor from the previous equilibrium, and
      // for a slender structure it rightly raises |r| a hundredfold or more (the linear
      // predictor ignores the shortening of the bent beam: halving it took 81 instead of 60
      // iterations for the 80-degree Hex20 cantilever of the tests).
      double step = 1.0;
      for (int ls = 0; ls < 12; ++ls, step *= 0.5) {
        as_dofs(trial) = as_dofs(x) + step * dx;
        const double trial_norm = evaluate(trial, lambda, StiffnessKind::None);
        if (std::isfinite(trial_norm) && (it == 0 || trial_norm <= 10 * r_norm)) break;
      }
      as_dofs(x) += step * dx;
      ++result.total_iterations;
    }
    if (after_each_load_step) after_each_load_step(s);
  }
  return result;
}

}  // namespace corotate
