// Preconditioners for the conjugate gradient solver.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "corotate/solvers/block_cholesky.hpp"

namespace corotate {

class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual void reset() {}
  // Rest node positions (3 x n) for preconditioners that build near-null-space modes.
  virtual void set_geometry(const Nodes&) {}
  // Node positions (3 x n) the next system is assembled at, for preconditioners that follow
  // the body's rotation.
  virtual void set_positions(const Nodes&) {}
  // Called once per solve with the current system matrix.
  virtual void compute(const BlockSparseMatrix& A) = 0;
  // z = P^-1 r.
  virtual void apply(const Vec& r, Vec& z) = 0;
};

// No preconditioning (plain CG): z = r.
class IdentityPreconditioner final : public Preconditioner {
 public:
  void compute(const BlockSparseMatrix&) override {}
  void apply(const Vec& r, Vec& z) override { z = r; }
};

// Inverse of the diagonal.
class JacobiPreconditioner final : public Preconditioner {
 public:
  void compute(const BlockSparseMatrix& A) override;
  void apply(const Vec& r, Vec& z) override { z = inverse_diagonal_.cwiseProduct(r); }

 private:
  Vec inverse_diagonal_;
};

// Inverse of each node's 3x3 diagonal block: couples the three axes of a node, which the
// rotated stiffness mixes.
class BlockJacobiPreconditioner final : public Preconditioner {
 public:
  void compute(const BlockSparseMatrix& A) override;
  void apply(const Vec& r, Vec& z) override;
  const Mat3& inverse_block(Index node) const { return inverse_blocks_[node]; }

 private:
  std::vector<Mat3> inverse_blocks_;
};

// Cholesky factorization of the first system matrix it sees (the rest state, when a body
// starts at rest), reused for every later solve. The rotated system matrix of a co-rotated
// body stays spectrally close to it, so CG needs few iterations while a step costs two
// triangular solves instead of a factorization.
class ReferenceFactorPreconditioner final : public Preconditioner {
 public:
  void reset() override { factor_ = BlockCholesky(); }
  void compute(const BlockSparseMatrix& A) override {
    if (factor_.empty()) factor_.factorize(A);
  }
  void apply(const Vec& r, Vec& z) override { factor_.solve(r, z); }

 private:
  BlockCholesky factor_;
};

enum class PreconditionerKind { None, Jacobi, BlockJacobi, ReferenceFactor, TwoLevel };

const std::vector<std::string>& preconditioner_names();  // in the order of PreconditionerKind
PreconditionerKind preconditioner_kind_from_name(const std::string& name);
const char* preconditioner_name(PreconditionerKind kind);
std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind);

}  // namespace corotate
