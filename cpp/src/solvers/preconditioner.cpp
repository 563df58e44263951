#include "corotate/solvers/preconditioner.hpp"

#include "corotate/solvers/two_level_preconditioner.hpp"

namespace corotate {

void JacobiPreconditioner::compute(const BlockSparseMatrix& A) {
  inverse_diagonal_.resize(A.num_dofs());
  for (Index i = 0; i < A.num_nodes(); ++i) {
    const auto d = A.block(A.diagonal_block(i)).diagonal();
    for (int r = 0; r < 3; ++r) {
      if (!(d(r) > 0)) throw SolverFailure("Jacobi preconditioner: non-positive diagonal entry at DOF " + std::to_string(3 * i + r));
      inverse_diagonal_(3 * i + r) = 1.0 / d(r);
    }
  }
}

void BlockJacobiPreconditioner::compute(const BlockSparseMatrix& A) {
  inverse_blocks_.resize(A.num_nodes());
  for (Index i = 0; i < A.num_nodes(); ++i) {
    const Mat3 block = A.block(A.diagonal_block(i));
    bool invertible = false;
    block.computeInverseWithCheck(inverse_blocks_[i], invertible);
    if (!invertible) throw SolverFailure("block-Jacobi preconditioner: singular diagonal block at node " + std::to_string(i));
  }
}

void BlockJacobiPreconditioner::apply(const Vec& r, Vec& z) {
  for (size_t i = 0; i < inverse_blocks_.size(); ++i) z.segment<3>(3 * i).noalias() = inverse_blocks_[i] * r.segment<3>(3 * i);
}

PreconditionerKind preconditioner_kind_from_name(const std::string& name) {
  if (name == "none") return PreconditionerKind::None;
  if (name == "jacobi") return PreconditionerKind::Jacobi;
  if (name == "block_jacobi") return PreconditionerKind::BlockJacobi;
  if (name == "reference_factor") return PreconditionerKind::ReferenceFactor;
  if (name == "two_level") return PreconditionerKind::TwoLevel;
  throw InvalidInput("unknown preconditioner '" + name + "' (choose none, jacobi, block_jacobi, reference_factor or two_level)");
}

const char* preconditioner_name(PreconditionerKind kind) {
  switch (kind) {
    case PreconditionerKind::None: return "none";
    case PreconditionerKind::Jacobi: return "jacobi";
    case PreconditionerKind::BlockJacobi: return "block_jacobi";
    case PreconditionerKind::ReferenceFactor: return "reference_factor";
    case PreconditionerKind::TwoLevel: return "two_level";
  }
  return "?";
}

std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind) {
  switch (kind) {
    case PreconditionerKind::None: return std::make_unique<IdentityPreconditioner>();
    case PreconditionerKind::Jacobi: return std::make_unique<JacobiPreconditioner>();
    case PreconditionerKind::BlockJacobi: return std::make_unique<BlockJacobiPreconditioner>();
    case PreconditionerKind::ReferenceFactor: return std::make_unique<ReferenceFactorPreconditioner>();
    case PreconditionerKind::TwoLevel: return std::make_unique<TwoLevelPreconditioner>();
  }
  throw InvalidInput("unknown preconditioner kind");
}

}  // namespace corotate
