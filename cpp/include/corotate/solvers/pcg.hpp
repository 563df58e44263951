// Preconditioned conjugate gradients with an iteration cap (paper 2.2): each iteration is
// one matrix-vector product, so capping the iterations trades accuracy for a bounded cost.
#pragma once

#include <memory>

#include "corotate/solvers/linear_solver.hpp"
#include "corotate/solvers/preconditioner.hpp"

namespace corotate {

// The defaults are corotate's default solver (corotate.PCG()): the fastest setting found to
// stay within 1% of a converged solve on the benchmark beam (bench/README.md).
// CG multiplies with the float32 copy of A that a preconditioner keeps for its own products
// (SinglePrecisionSymmetric: half the bytes of the double product, which is bound by them)
// when the tolerance is this far above float32's rounding: the system it then solves
// differs from A by about 1e-7 of its entries (rounded once, or summed in float32 where the
// step assembles straight into the copy: single_precision_target), a thousand times below
// the residual asked for. Tighter tolerances (the converged references, statics) stay in
// double.
constexpr double kSinglePrecisionProductTolerance = 1e-4;

struct PCGSettings {
  int max_iterations = 20;   // cap; the solve stops there even when not converged
  // Relative residual |b - A x| / |b| at which CG stops; 0: the preconditioner's own
  // (Preconditioner::default_tolerance: 2e-2 for two_level, 1e-2 for the others).
  double tolerance = 0;
  bool warm_start = true;    // start from the x passed in (e.g. the previous step's answer)
  PreconditionerKind preconditioner = PreconditionerKind::Auto;
  void validate() const;     // throws InvalidInput naming the parameter
  // The tolerance in force when it is left at 0 (the preconditioner's) or set.
  double tolerance_or(double preconditioner_default) const {
    return tolerance > 0 ? tolerance : preconditioner_default;
  }
  // Whether CG multiplies in float32 (every default tolerance is loose enough).
  bool single_precision_products() const { return tolerance == 0 || tolerance >= kSinglePrecisionProductTolerance; }
};

class PCG final : public LinearSolver {
 public:
  explicit PCG(const PCGSettings& settings = {});
  const PCGSettings& settings() const { return settings_; }
  void reset() override { preconditioner_->reset(); }
  // Keeps the preconditioner (a reference factorization or two-level hierarchy built for the
  // earlier constraints) and applies it as P Pc P + (I - P) with P the projection onto the
  // free DOFs, which is exact on the decoupled fixed rows and SPD. Fixing, releasing or
  // attaching a few nodes is a low-rank change of the system: it costs a few CG iterations,
  // not a rebuild (set_solver or reset rebuilds).
  void constraints_changed(const FixedDofs& fixed) override {
    fixed_dofs_ = fixed.list();
    fixed_residual_.resize(static_cast<Index>(fixed_dofs_.size()));
  }
  void set_geometry(const Nodes& rest) override { preconditioner_->set_geometry(rest); }
  void set_positions(const Nodes& x) override { preconditioner_->set_positions(x); }
  void set_diagonal_terms(const DiagonalTerms* terms) override { preconditioner_->set_diagonal_terms(terms); }
  void set_coupling(const SystemCoupling* coupling) override {
    LinearSolver::set_coupling(coupling);
    preconditioner_->set_coupling(coupling);
  }
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override;
  // At tolerances where CG multiplies in float32 anyway, the preconditioner's float32 copy,
  // once it has one (the two-level preconditioner after its first system).
  SinglePrecisionSymmetric* single_precision_target() override {
    return settings_.single_precision_products() ? preconditioner_->assembly_target() : nullptr;
  }
  SolveStats solve_single_precision(const Vec& b, Vec& x) override;
  void request_accuracy(double tolerance, int max_iterations) override {
    requested_tolerance_ = tolerance;
    requested_iterations_ = max_iterations;
  }
  // CG reads A through multiply_symmetric only: the preconditioner decides.
  bool needs_lower_blocks() const override { return preconditioner_->needs_lower_blocks(); }
  void save_state() override { preconditioner_->save_state(); }
  void restore_state() override { preconditioner_->restore_state(); }

 private:
  double requested_tolerance_ = 0;  // request_accuracy, for the next solve (0: none)
  int requested_iterations_ = 0;
  PCGSettings settings_;
  std::unique_ptr<Preconditioner> preconditioner_;
  void precondition();  // z = preconditioned r, with the fixed DOFs decoupled
  // The iterations once the preconditioner is computed, multiplying with single if given,
  // else with A.
  SolveStats iterate(const BlockSparseMatrix* A, const SinglePrecisionSymmetric* single, const Vec& b, Vec& x);
  // out = A v, in double or with the preconditioner's float32 copy (single)
  void multiply(const BlockSparseMatrix* A, const SinglePrecisionSymmetric* single, const Vec& v, Vec& out) const;
  std::vector<Index> fixed_dofs_;  // ascending
  Vec fixed_residual_;
  Vec r_, z_, p_, q_;  // work vectors, sized on first use
};

}  // namespace corotate
