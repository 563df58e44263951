// Interface of the solvers for the symmetric positive definite systems of a step.
#pragma once

#include <functional>

#include "corotate/fem/fixed_dofs.hpp"
#include "corotate/solvers/diagonal_terms.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class SinglePrecisionSymmetric;

struct SolveStats {
  int iterations = 0;              // CG iterations (0 for a direct solve)
  double relative_residual = 0.0;  // |b - A x| / |b| at exit
  bool converged = true;           // tolerance met (a capped CG may stop before)
  double tolerance = 0.0;          // the relative residual CG aimed at (0 for a direct solve)
};

// |b - A x| / |b| (|b - A x| when b = 0), what every solver reports; work: any vector,
// resized to the system (no allocation after the first call).
inline double relative_residual(const BlockSparseMatrix& A, const Vec& b, const Vec& x, Vec& work) {
  work.resize(b.size());
  A.multiply(x, work);
  work -= b;
  const double bn = b.norm();
  return bn > 0 ? work.norm() / bn : work.norm();
}

// A symmetric term of the system that is not in its sparse pattern: the coupling between
// nodes that share no element but touch (two parts of a body in contact: a node and the
// corners of the triangle it presses on). A solve multiplies with A + C; C leaves the rows and
// columns of fixed DOFs alone.
class SystemCoupling {
 public:
  virtual ~SystemCoupling() = default;
  virtual void multiply_add(const Vec& x, Vec& y) const = 0;  // y += C x
  // Calls visit(i, j, B) for each block B that C adds at (i, j), i != j, both orders; a pair
  // may come more than once (the blocks add up). For a factor of A + C (coupled_matrix.hpp).
  virtual void for_each_block(const std::function<void(Index, Index, const Mat3&)>& visit) const = 0;
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  // The next solves are of A + coupling (null: of A alone); the caller keeps it alive and
  // clears it after its solves. Iterative solvers add it to their products (PCG passes it on
  // to its preconditioner too); the direct solver factorizes A + C (coupled_matrix.hpp).
  virtual void set_coupling(const SystemCoupling* coupling) { coupling_ = coupling; }
  const SystemCoupling* coupling() const { return coupling_; }
  // The next solves' diagonal terms (null: none), kept alive and cleared like the coupling;
  // only solvers whose preconditioner has a coarse level built once use them.
  virtual void set_diagonal_terms(const DiagonalTerms*) {}
  // Forget everything cached about earlier systems (pattern, constraints or dt changed).
  virtual void reset() = 0;
  // The fixed DOFs of the systems to come changed (their rows and columns are projected out:
  // identity rows, see FixedDofs). The pattern is the same, so the default forgets only what
  // a solver cannot reuse; see the overrides.
  virtual void constraints_changed(const FixedDofs&) { reset(); }
  // Rest node positions (3 x n), for solvers whose preconditioner uses the geometry.
  virtual void set_geometry(const Nodes&) {}
  // Node positions (3 x n) the next system is assembled at (the integrators and the static
  // solver give them before each solve), for solvers whose preconditioner follows the
  // body's rotation.
  virtual void set_positions(const Nodes&) {}
  // Solve A x = b. x holds the initial guess on entry (used by warm-started iterative
  // solvers) and the solution on exit.
  virtual SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) = 0;
  // The next solve's A is the last solve's, value for value (a step that keeps its matrix,
  // kept_system.hpp): a solver that factorizes may solve with its last factor of it.
  virtual void same_matrix_next() {}
  // Whether the next solve reads blocks that BlockSparseMatrix::multiply_symmetric does not
  // (BlockSparseMatrix::is_product_block): if not, the step may skip assembling them
  // (Request::lower_blocks).
  virtual bool needs_lower_blocks() const { return true; }
  // A float32 system that the next solve can take in place of a double one, or nullptr:
  // the implicit step then assembles straight into it (forces and stiffness in one sweep,
  // ForceModel::assembles_single_precision; the mass and the constraints added as for A)
  // and calls solve_single_precision. Valid until the next call to this solver.
  virtual SinglePrecisionSymmetric* single_precision_target() { return nullptr; }
  // solve() with A the system assembled into single_precision_target().
  virtual SolveStats solve_single_precision(const Vec& /*b*/, Vec& /*x*/) {
    throw InvalidInput("this solver takes no float32 system");
  }
  // Simulation::step keeps what the solves of a call change and would make the next call's
  // answers differ (a preconditioner's rotation warm starts, a factor refreshed), and
  // restores it when the call fails: the state is then that of a twin that never made it.
  // The next solve (only) aims at least at this relative residual, with at least this many
  // iterations allowed: for a caller that decides something from the answer (the contact
  // active set at an impact), where the step's usual loose tolerance would decide by noise.
  // Direct solvers are exact anyway.
  virtual void request_accuracy(double /*tolerance*/, int /*max_iterations*/) {}
  virtual void save_state() {}
  virtual void restore_state() {}

 protected:
  const SystemCoupling* coupling_ = nullptr;
};

// Sets a solver's coupling and diagonal terms for a scope (the solves of one step) and
// clears them after.
class CouplingScope {
 public:
  CouplingScope(LinearSolver& solver, const SystemCoupling* coupling, const DiagonalTerms* terms = nullptr)
      : solver_(solver) {
    solver_.set_coupling(coupling);
    solver_.set_diagonal_terms(terms);
  }
  ~CouplingScope() {
    solver_.set_coupling(nullptr);
    solver_.set_diagonal_terms(nullptr);
  }
  CouplingScope(const CouplingScope&) = delete;
  CouplingScope& operator=(const CouplingScope&) = delete;

 private:
  LinearSolver& solver_;
};

}  // namespace corotate
