// Preconditioners for the conjugate gradient solver.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "corotate/solvers/block_cholesky.hpp"
#include "corotate/solvers/diagonal_terms.hpp"
#include "corotate/solvers/node_rotations.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate {

class SinglePrecisionSymmetric;
class SystemCoupling;

class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual void reset() {}
  // Rest node positions (3 x n) for preconditioners that build near-null-space modes.
  virtual void set_geometry(const Nodes&) {}
  // Node positions (3 x n) the next system is assembled at, for preconditioners that follow
  // the body's rotation.
  virtual void set_positions(const Nodes&) {}
  // The diagonal terms (diagonal_terms.hpp) in the systems of the next compute() calls, or
  // null; the caller keeps them alive. Only a coarse level built once needs them.
  virtual void set_diagonal_terms(const DiagonalTerms*) {}
  // The coupling of the next compute() calls' systems (linear_solver.hpp), or null; the
  // caller keeps it alive. A factor of A + C needs it (reference_factor).
  virtual void set_coupling(const SystemCoupling*) {}
  // Called once per solve with the current system matrix.
  virtual void compute(const BlockSparseMatrix& A) = 0;
  // z = P^-1 r.
  virtual void apply(const Vec& r, Vec& z) = 0;
  // Told after each solve whether CG reached its tolerance within its cap: preconditioners
  // built once may rebuild when they stop paying.
  virtual void solved(bool /*converged*/) {}
  // Whether the next compute() or apply() reads blocks that multiply_symmetric does not
  // (BlockSparseMatrix::is_product_block); true unless a preconditioner knows better.
  virtual bool needs_lower_blocks() const { return true; }
  // The float32 copy of the matrix that compute() made for its own products, if it keeps one
  // (valid until the next compute()): CG may multiply with it too (pcg.hpp).
  virtual const SinglePrecisionSymmetric* single_precision_matrix() const { return nullptr; }
  // Told once by CG whether it multiplies with single_precision_matrix() (its tolerance
  // decides): a preconditioner that keeps the copy only for CG then need not make it.
  virtual void set_single_precision_products(bool) {}
  // Where the next system may be assembled in float32 instead of being passed to compute()
  // (LinearSolver::single_precision_target): that copy, once it has a layout; else nullptr.
  virtual SinglePrecisionSymmetric* assembly_target() { return nullptr; }
  // compute() for the system assembled into assembly_target().
  virtual void compute_assembled() { throw InvalidInput("this preconditioner takes no float32 system"); }
  // CG's tolerance when PCGSettings leave it at 0: the loosest relative residual at which
  // the implicit step stays as close to a converged solve as the benchmark's budget allows.
  // The two-level cycle removes the low modes' error in every iteration, so what a residual
  // leaves behind is high-frequency and moves the body little: its default is looser
  // (bench/README.md, "fourth round").
  virtual double default_tolerance() const { return 1e-2; }
  // LinearSolver::save_state and restore_state, for what apply() depends on.
  virtual void save_state() {}
  virtual void restore_state() {}
};

// No preconditioning (plain CG): z = r.
class IdentityPreconditioner final : public Preconditioner {
 public:
  void compute(const BlockSparseMatrix&) override {}
  void apply(const Vec& r, Vec& z) override { z = r; }
  bool needs_lower_blocks() const override { return false; }
};

// Inverse of the diagonal.
class JacobiPreconditioner final : public Preconditioner {
 public:
  void compute(const BlockSparseMatrix& A) override;
  void apply(const Vec& r, Vec& z) override { z = inverse_diagonal_.cwiseProduct(r); }
  bool needs_lower_blocks() const override { return false; }

 private:
  Vec inverse_diagonal_;
};

// Inverse of each node's 3x3 diagonal block: couples the three axes of a node, which the
// rotated stiffness mixes.
class BlockJacobiPreconditioner final : public Preconditioner {
 public:
  void compute(const BlockSparseMatrix& A) override;
  void compute(const SinglePrecisionSymmetric& A);  // from a float32 system's diagonal blocks
  void apply(const Vec& r, Vec& z) override;
  const Mat3& inverse_block(Index node) const { return inverse_blocks_[node]; }
  bool needs_lower_blocks() const override { return false; }  // the diagonal blocks only

 private:
  void invert(Index node, const Mat3& block);  // throws NotPositiveDefinite when singular
  std::vector<Mat3> inverse_blocks_;
};

// Cholesky factorization of the first system matrix it sees (the rest state, when a body
// starts at rest), reused for every later solve. The rotated system matrix of a co-rotated
// body stays spectrally close to it once the body's rotation is taken out, so CG needs few
// iterations while a step costs two triangular solves instead of a factorization.
// Given the positions each system is assembled at (set_positions), the factor is applied in
// each node's turned frame, z = R B0 R^T r (node_rotations.hpp): without that, a body that
// swings or spins through a large angle (the armadillo hanging from a point) made the frozen
// factor a poor fit and the capped CG ran away.
// When a solve still ends at its cap, the next one factorizes its own matrix afresh (and
// measures rotations from there): the body has changed more than rotations explain (large
// strains, a crumpling sheet whose matrix may be indefinite, which the factorization then
// reports), as SOFA's warp preconditioner refreshes its factor every few steps.
class ReferenceFactorPreconditioner final : public Preconditioner {
 public:
  void reset() override {
    factor_ = BlockCholesky();
    rotations_ = NodeRotations();
  }
  void set_positions(const Nodes& x) override {
    positions_ = x;  // no allocation once sized
    positions_pending_ = true;
  }
  void compute(const BlockSparseMatrix& A) override;
  void apply(const Vec& r, Vec& z) override;
  // Asks for a fresh factor after a solve that ends at its cap, and when one pays for it:
  // - when contacts first appear (diagonal terms, the springs of obstacles, in a system whose
  //   factor has none; or a coupling, contact between parts, that the factor leaves out);
  // - when the applications beyond the fewest since the last factorization (plus one per
  //   solve) add up to what a numeric refactorization costs (kRefreshCostScale): a body that
  //   settled far from the state it was factorized at, a landing, a body lifted off,
  //   contacts moved elsewhere. (With contacts only before: Table 1's cage, factorized at
  //   rest, sagged under gravity and took 2.64 CG iterations per step over 3,000 steps where
  //   refreshes make it 1.46: `python -m studies.table1_dog --phases 3000`. A fixed 40
  //   before that: the cage dropped on the floor ran 3-5 iterations per step for 20-30 steps
  //   at a time where a fresh factor gives one.)
  // The contacts' diagonal blocks are in A already; a factor of A takes them in.
  void solved(bool converged) override;
  void set_diagonal_terms(const DiagonalTerms* terms) override { terms_ = terms; }
  // The next factorization is of A + C (coupled_matrix.hpp) while a coupling is set: a factor
  // of A alone leaves CG one iteration per contact between parts to find.
  void set_coupling(const SystemCoupling* coupling) override { coupling_ = coupling; }
  // A refresh's price in CG iterations: the factor's flop count in solves
  // (BlockCholesky::refactorization_cost_in_solves) times this. On Table 1's cage dropped on
  // the floor a numeric refactorization took the time of 22 solves, about 15 iterations (a
  // solve and a product each), where the flop count says 9.7 solves.
  static constexpr double kRefreshCostScale = 1.5;
  // The factor's BlockCholesky::refactorization_cost_in_solves.
  double factor_cost_in_solves() const { return factor_.refactorization_cost_in_solves(); }
  // Only to factorize (the first system, or after a capped solve).
  bool needs_lower_blocks() const override { return factor_.empty() || refresh_; }
  // A float32 copy of each system for CG's products (when CG multiplies in float32), as the
  // two-level preconditioner keeps; between factorizations the step may assemble straight
  // into it.
  void set_single_precision_products(bool on) override { single_ = on; }
  const SinglePrecisionSymmetric* single_precision_matrix() const override {
    return single_ && A_single_.has_layout() ? &A_single_ : nullptr;
  }
  SinglePrecisionSymmetric* assembly_target() override {
    return single_ && !factor_.empty() && !refresh_ && A_single_.has_layout() ? &A_single_ : nullptr;
  }
  void compute_assembled() override;
  // Factorizations so far (the first and every refresh).
  int factorizations() const { return factorizations_; }
  // The rotations' warm starts are copied; a factor refreshed since save_state is moved
  // aside (with the rotations built for it) rather than copied at every call.
  void save_state() override;
  void restore_state() override;

 private:
  BlockCholesky factor_;
  struct Saved {
    bool refresh = false;
    int factorizations = 0;
    bool factor_replaced = false;  // factor and rotations below hold the saved ones
    bool factor_coupled = false, factor_contacts = false;
    int fewest = 0, excess = 0;
    BlockCholesky factor;
    NodeRotations rotations;
  } saved_;
  bool refresh_ = false;
  int factorizations_ = 0;
  const SystemCoupling* coupling_ = nullptr;
  const DiagonalTerms* terms_ = nullptr;
  bool factor_coupled_ = false;   // the factor is of A + C
  bool factor_contacts_ = false;  // the factor's system had contacts (terms or coupling)
  int applies_ = 0;               // in the current solve
  int fewest_ = 0, excess_ = 0;   // applications per solve since the factorization (solved())
  bool contacts_now() const { return coupling_ || (terms_ && !terms_->empty()); }
  NodeRotations rotations_;  // empty until positions arrive at the build
  Nodes positions_;
  bool positions_pending_ = false;
  SinglePrecisionSymmetric A_single_;
  bool single_ = true;
  // Checks the pending positions and turns the rotations to them (unless rebuilding).
  void turn(Index num_nodes, bool rebuilding);
};

enum class PreconditionerKind { None, Jacobi, BlockJacobi, ReferenceFactor, TwoLevel, Auto };

// The default: the reference factor below kAutoFactorDofs unknowns, the two-level
// preconditioner from there on, chosen at the first system it sees. Small systems factorize
// with little fill, and two triangular solves then cost less than a V-cycle and need fewer
// iterations; large ones fill in (the factor's size and set-up grow as n^(4/3) or worse).
// Measured with capped, warm-started PCG (cap 20, 1e-2), solve time per step, one core:
// the 720-tet armadillo cage (909 DOFs), 0.063 against 0.31 ms; its 6,251-tet cage (4,983),
// 1.18 against 2.14 ms; the 1,920-tet beam (1,575), 0.20 against 0.29 ms; but the
// 15,360-tet beam (9,963), 3.85 against 3.38 ms, with a first step of 370 against 59 ms.
inline constexpr Index kAutoFactorDofs = 6000;

class AutoPreconditioner final : public Preconditioner {
 public:
  void reset() override {
    chosen_.reset();
    kind_ = PreconditionerKind::Auto;
  }
  void set_geometry(const Nodes& rest) override {  // kept: a reset() chooses again
    rest_ = rest;
    if (chosen_) chosen_->set_geometry(rest);
  }
  // Kept only until the choice, then passed straight on (no second copy per step).
  void set_positions(const Nodes& x) override {
    if (chosen_) chosen_->set_positions(x);
    else positions_ = x;
  }
  void set_diagonal_terms(const DiagonalTerms* terms) override {  // kept for the choice
    terms_ = terms;
    if (chosen_) chosen_->set_diagonal_terms(terms);
  }
  void set_coupling(const SystemCoupling* coupling) override {  // kept for the choice
    coupling_ = coupling;
    if (chosen_) chosen_->set_coupling(coupling);
  }
  void compute(const BlockSparseMatrix& A) override;
  void apply(const Vec& r, Vec& z) override { chosen_->apply(r, z); }
  void solved(bool converged) override { chosen_->solved(converged); }
  bool needs_lower_blocks() const override { return !chosen_ || chosen_->needs_lower_blocks(); }
  const SinglePrecisionSymmetric* single_precision_matrix() const override {
    return chosen_ ? chosen_->single_precision_matrix() : nullptr;
  }
  SinglePrecisionSymmetric* assembly_target() override { return chosen_ ? chosen_->assembly_target() : nullptr; }
  void set_single_precision_products(bool on) override {  // kept: a reset() chooses again
    single_ = on;
    if (chosen_) chosen_->set_single_precision_products(on);
  }
  void compute_assembled() override { chosen_->compute_assembled(); }
  double default_tolerance() const override {
    return chosen_ ? chosen_->default_tolerance() : Preconditioner::default_tolerance();
  }
  // ReferenceFactor or TwoLevel once a system was seen; Auto before.
  PreconditionerKind chosen() const { return kind_; }
  // A choice made in the failed call is undone (made again, the same, by the next).
  void save_state() override {
    chosen_at_save_ = chosen_ != nullptr;
    if (chosen_) chosen_->save_state();
  }
  void restore_state() override {
    if (!chosen_at_save_) reset();
    else chosen_->restore_state();
  }

 private:
  std::unique_ptr<Preconditioner> chosen_;
  bool chosen_at_save_ = false;
  PreconditionerKind kind_ = PreconditionerKind::Auto;
  Nodes rest_, positions_;  // passed on to the one chosen
  bool single_ = true;
  const DiagonalTerms* terms_ = nullptr;
  const SystemCoupling* coupling_ = nullptr;
};

const std::vector<std::string>& preconditioner_names();  // in the order of PreconditionerKind
PreconditionerKind preconditioner_kind_from_name(const std::string& name);
const char* preconditioner_name(PreconditionerKind kind);
std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind);

}  // namespace corotate
