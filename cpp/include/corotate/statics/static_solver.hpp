// Static equilibrium f_int(x) + load = 0 on the free DOFs, by Newton iterations with load
// stepping: the load is applied in equal increments, each solved to the tolerance before
// the next. Each iteration solves K(x) dx = f_int(x) + lambda * load with fixed DOFs held.
//
// A Newton step that would make the residual non-finite, or (after the first iteration of a
// load step, the tangent predictor) ten times larger, is halved.
// Displacement control: with `prescribed` given, the fixed DOFs move in the same load steps
// from their positions on entry to the prescribed ones, so large prescribed displacements
// are reached gradually too. For the linear model one iteration is exact. K is the model's
// Tangent stiffness, exact for every model (quadratic convergence). Where it is symmetric it
// is solved by `solver`; where it is not (co-rotated hexes, ForceModel::symmetric_tangent())
// by a sparse LU (LuSolver). Where the exact tangent is indefinite (or singular) the
// iteration falls back to the model's positive semi-definite stiffness, solved by `solver`.
#pragma once

#include <functional>
#include <vector>

#include "corotate/fem/fixed_dofs.hpp"
#include "corotate/models/force_model.hpp"
#include "corotate/solvers/linear_solver.hpp"

namespace corotate {

struct StaticSettings {
  int load_steps = 1;          // equal load increments
  double tolerance = 1e-8;     // |residual| <= tolerance * |load| on the free DOFs
  int max_iterations = 100;    // per load step
  void validate() const;
};

struct StaticResult {
  // residual norm (relative to the load) before each iteration, one list per load step
  std::vector<std::vector<double>> residual_history;
  int total_iterations = 0;
};

// x: 3 x n positions, start of the iteration on entry and equilibrium on exit; fixed DOFs
// keep their values in x, or, with prescribed (3 x n, only fixed DOFs read), end at those.
// load: 3 x n external nodal forces.
// after_each_load_step (optional) is called with the number of load steps done (progress
// reports, interruption checks); what it throws ends the solve.
// Throws SolverFailure (with the residuals) when a load step does not converge; x is then
// left at the last iterate, so callers that need the old state must keep a copy.
StaticResult solve_static(ForceModel& model, Nodes& x, const Nodes& load, const FixedDofs& fixed,
                          const StaticSettings& settings, LinearSolver& solver, const Nodes* prescribed = nullptr,
                          const std::function<void(int done)>& after_each_load_step = {});

}  // namespace corotate
