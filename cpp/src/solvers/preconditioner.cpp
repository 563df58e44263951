#include "corotate/solvers/preconditioner.hpp"

#include "corotate/parallel.hpp"
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

void BlockJacobiPreconditioner::compute(const BlockSparseMatrix& A) {
  inverse_blocks_.resize(A.num_nodes());
  for (Index i = 0; i < A.num_nodes(); ++i) {
    const Mat3 block = A.block(A.diagonal_block(i));
    bool invertible = false;
    block.computeInverseWithCheck(inverse_blocks_[i], invertible);
    if (!invertible)
      throw NotPositiveDefinite("block-Jacobi preconditioner: singular diagonal block at node " + std::to_string(i));
  }
}

void BlockJacobiPreconditioner::apply(const Vec& r, Vec& z) {
  const Index n = static_cast<Index>(inverse_blocks_.size());
  COROTATE_PARALLEL_FOR(n >= 512)
  for (Index i = 0; i < n; ++i) z.segment<3>(3 * i).noalias() = inverse_blocks_[i] * r.segment<3>(3 * i);
}

const std::vector<std::string>& preconditioner_names() {
  static const std::vector<std::string> names = {"none", "jacobi", "block_jacobi", "reference_factor", "two_level"};
  return names;
}

PreconditionerKind preconditioner_kind_from_name(const std::string& name) {
  const auto& names = preconditioner_names();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<PreconditionerKind>(i);
  throw InvalidInput("unknown preconditioner '" + name +
                     "' (choose none, jacobi, block_jacobi, reference_factor or two_level)");
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
  }
  throw InvalidInput("unknown preconditioner kind");
}

}  // namespace corotate
