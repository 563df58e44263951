#include "corotate/solvers/preconditioner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "corotate/parallel.hpp"
#include "corotate/solvers/coupled_matrix.hpp"
#include "corotate/solvers/two_level_preconditioner.hpp"

namespace corotate {

void JacobiPreconditioner::compute(const BlockSparseMatrix& A) {
  inverse_diagonal_.resize(A.num_dofs());
  for (Index i = 0; i < A.num_nodes(); ++i) {
    const auto d = A.block(A.diagonal_block(i)).diagonal();
    for (int r = 0; r < 3; ++r) {
      if (!(d(r) > 0))
        throw NotPositiveDefinite("Jacobi preconditioner: non-positive diagonal entry at DOF " +
                                  std::to_string(3 * i + r));
      inverse_diagonal_(3 * i + r) = 1.0 / d(r);
    }
  }
}

void BlockJacobiPreconditioner::invert(Index node, const Mat3& block) {
  bool invertible = false;
  block.computeInverseWithCheck(inverse_blocks_[node], invertible);
  if (!invertible)
    throw NotPositiveDefinite("block-Jacobi preconditioner: singular diagonal block at node " + std::to_string(node));
}

void BlockJacobiPreconditioner::compute(const BlockSparseMatrix& A) {
  inverse_blocks_.resize(A.num_nodes());
  for (Index i = 0; i < A.num_nodes(); ++i) invert(i, A.block(A.diagonal_block(i)));
}

void BlockJacobiPreconditioner::compute(const SinglePrecisionSymmetric& A) {
  // Every step's smoother setup: the symmetric blocks' inverses by their cofactors, in one
  // pass without a call or a branch per node (a general 3x3 inverse with a check per node
  // took 1.6 % of a step at 15,360 tets), and exactly symmetric. Only if some block is
  // singular (or not finite) does a second pass find the first one.
  const Index n = A.num_nodes();
  inverse_blocks_.resize(n);
  const double s = A.unscale();
  bool all_invertible = true;
  for (Index i = 0; i < n; ++i) {
    const float* d = A.diagonal_block_values(i);
    const double a = s * d[0], b = s * d[1], c = s * d[2], e = s * d[4], f = s * d[5], k = s * d[8];
    const double c00 = e * k - f * f, c01 = c * f - b * k, c02 = b * f - c * e;
    const double c11 = a * k - c * c, c12 = b * c - a * f, c22 = a * e - b * b;
    const double det = a * c00 + b * c01 + c * c02;
    all_invertible &= (std::abs(det) > 0) & (std::abs(det) <= std::numeric_limits<double>::max());
    const double inv = 1 / det;
    inverse_blocks_[i] << c00 * inv, c01 * inv, c02 * inv, c01 * inv, c11 * inv, c12 * inv, c02 * inv, c12 * inv,
        c22 * inv;
  }
  if (!all_invertible)
    for (Index i = 0; i < n; ++i) invert(i, A.diagonal_block(i));  // throws at the first singular one
}

void BlockJacobiPreconditioner::apply(const Vec& r, Vec& z) {
  const Index n = static_cast<Index>(inverse_blocks_.size());
  COROTATE_PARALLEL_FOR(n >= 512)
  for (Index i = 0; i < n; ++i) z.segment<3>(3 * i).noalias() = inverse_blocks_[i] * r.segment<3>(3 * i);
}

void ReferenceFactorPreconditioner::turn(Index num_nodes, bool rebuilding) {
  if (positions_.cols() != 0 && positions_.cols() != num_nodes)
    throw InvalidInput("reference_factor preconditioner: positions of " + std::to_string(positions_.cols()) +
                       " nodes for a " + std::to_string(num_nodes) + "-node system");
  if (!rebuilding && positions_pending_ && !rotations_.empty()) rotations_.update(positions_);
  positions_pending_ = false;
}

void ReferenceFactorPreconditioner::solved(bool converged) {
  refresh_ = refresh_ || !converged;
  if ((coupling_ && !factor_coupled_) || (contacts_now() && !factor_contacts_)) refresh_ = true;
  fewest_ = std::min(fewest_, applies_);
  excess_ += std::max(0, applies_ - fewest_ - 1);
  if (excess_ >= kRefreshCostScale * factor_.refactorization_cost_in_solves()) refresh_ = true;
  applies_ = 0;
}

void ReferenceFactorPreconditioner::save_state() {
  saved_.refresh = refresh_;
  saved_.factorizations = factorizations_;
  saved_.fewest = fewest_;
  saved_.excess = excess_;
  saved_.factor_replaced = false;
  saved_.factor = BlockCholesky();  // (a factor replaced in the last call, no longer needed)
  rotations_.save_state();
}

void ReferenceFactorPreconditioner::restore_state() {
  if (saved_.factor_replaced) {
    factor_ = std::move(saved_.factor);
    rotations_ = std::move(saved_.rotations);
    factor_coupled_ = saved_.factor_coupled;
    factor_contacts_ = saved_.factor_contacts;
    saved_.factor_replaced = false;
  }
  rotations_.restore_state();
  refresh_ = saved_.refresh;
  factorizations_ = saved_.factorizations;
  fewest_ = saved_.fewest;
  excess_ = saved_.excess;
  applies_ = 0;
}

void ReferenceFactorPreconditioner::compute(const BlockSparseMatrix& A) {
  if (factor_.empty() || refresh_) {
    turn(A.num_nodes(), true);  // (the rotations are built afresh below)
    refresh_ = false;
    if (!saved_.factor_replaced) {  // the first replacement since save_state: keep the old
      saved_.factor = factor_;  // (a copy: factor_ keeps its ordering and structure, and a
                                // matrix of the same pattern is then factorized numerically only)
      saved_.rotations = std::move(rotations_);
      saved_.factor_coupled = factor_coupled_;
      saved_.factor_contacts = factor_contacts_;
      saved_.factor_replaced = true;
    }
    rotations_ = NodeRotations();
    // (Throws NotPositiveDefinite for an indefinite matrix.)
    factor_coupled_ = coupling_ != nullptr;
    factor_contacts_ = contacts_now();
    fewest_ = std::numeric_limits<int>::max();
    excess_ = 0;
    if (coupling_) factor_.factorize(with_coupling(A, *coupling_));
    else factor_.factorize(A);
    ++factorizations_;
    // Built at the positions A was assembled at: rotations are measured from there.
    if (positions_.cols() != 0) rotations_.build(A, positions_);
  } else {
    turn(A.num_nodes(), false);
  }
  if (single_) A_single_.assign(A);
}

void ReferenceFactorPreconditioner::compute_assembled() {
  if (factor_.empty() || refresh_) throw InvalidInput("reference_factor preconditioner: a float32 system to factorize");
  turn(A_single_.num_nodes(), false);
}

void ReferenceFactorPreconditioner::apply(const Vec& r, Vec& z) {
  // Where CG multiplies in float32 (a loose tolerance) the factor sums in float32 too.
  ++applies_;
  const Mat3* turn = rotations_.rotated() ? rotations_.rotations().data() : nullptr;
  single_ ? factor_.solve_single(r, z, turn) : factor_.solve(r, z, turn);
}

void AutoPreconditioner::compute(const BlockSparseMatrix& A) {
  if (!chosen_) {
    kind_ = A.num_dofs() < kAutoFactorDofs ? PreconditionerKind::ReferenceFactor : PreconditionerKind::TwoLevel;
    chosen_ = make_preconditioner(kind_);
    if (rest_.cols() != 0) chosen_->set_geometry(rest_);
    chosen_->set_single_precision_products(single_);
    if (positions_.cols() != 0) chosen_->set_positions(positions_);
    chosen_->set_diagonal_terms(terms_);
    chosen_->set_coupling(coupling_);
  }
  chosen_->compute(A);
}

const std::vector<std::string>& preconditioner_names() {
  static const std::vector<std::string> names = {"none",      "jacobi", "block_jacobi", "reference_factor",
                                                 "two_level", "auto"};
  return names;
}

PreconditionerKind preconditioner_kind_from_name(const std::string& name) {
  const auto& names = preconditioner_names();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<PreconditionerKind>(i);
  throw InvalidInput("unknown preconditioner '" + name +
                     "' (choose none, jacobi, block_jacobi, reference_factor, two_level or auto)");
}

const char* preconditioner_name(PreconditionerKind kind) {
  return preconditioner_names()[static_cast<int>(kind)].c_str();
}

std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind) {
  switch (kind) {
    case PreconditionerKind::None: return std::make_unique<IdentityPreconditioner>();
    case PreconditionerKind::Jacobi: return std::make_unique<JacobiPreconditioner>();
    case PreconditionerKind::BlockJacobi: return std::make_unique<BlockJacobiPreconditioner>();
    case PreconditionerKind::ReferenceFactor: return std::make_unique<ReferenceFactorPreconditioner>();
    case PreconditionerKind::TwoLevel: return std::make_unique<TwoLevelPreconditioner>();
    case PreconditionerKind::Auto: return std::make_unique<AutoPreconditioner>();
  }
  throw InvalidInput("unknown preconditioner kind");
}

}  // namespace corotate
