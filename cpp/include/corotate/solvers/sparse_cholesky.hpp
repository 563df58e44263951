// Sparse Cholesky factorization of a symmetric positive definite matrix, for the direct
// solver (Direct(), Newton steps, statics) and the coarse level of the two-level
// preconditioner. Three backends:
// - SuiteSparse CHOLMOD (supernodal, with the ordering CHOLMOD picks: AMD, or METIS where it
//   pays) when the build found it (Debian: libsuitesparse-dev);
// - the library's own supernodal factor (supernodal_cholesky.hpp) otherwise: a plain
//   `pip install .` or the prebuilt wheel. At 122,880 tets (70,227 unknowns) it factorizes in
//   about 1.3x CHOLMOD's time with OpenBLAS, and 5x faster than CHOLMOD with Debian's
//   default reference BLAS (bench/README.md); Eigen's SimplicialLDLT took 81 s there;
// - Eigen's SimplicialLDLT below kSupernodalFromDofs unknowns, where supernodes are too small
//   for dense kernels to pay: with Debian's reference BLAS CHOLMOD factorized the 828-DOF
//   Table 1 cage in 0.92 ms against 0.48 ms for SimplicialLDLT.
// Both supernodal factors are solved by our own sweeps (supernodal_solve.hpp), not by
// cholmod_solve (which runs them through BLAS: slow with the reference BLAS).
#pragma once

#include <Eigen/SparseCore>
#include <memory>

#include "corotate/common.hpp"

namespace corotate {

class SparseCholesky {
 public:
  // Auto: Eigen below kSupernodalFromDofs unknowns, else CHOLMOD when built with it, else
  // the library's own supernodal factor (supernodal_cholesky.hpp).
  enum class Backend { Auto, Eigen, Cholmod, Supernodal };
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  static constexpr Index kSupernodalFromDofs = 4000;
  static bool have_cholmod();
  // Backend::Cholmod in a build without CHOLMOD throws InvalidInput.
  explicit SparseCholesky(Backend backend = Backend::Auto);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  // "cholmod" or "eigen": the backend of the last analysis, or the one asked for; "auto"
  // before Auto has seen a matrix.
  const char* backend_name() const;
  // Symbolic analysis of A's pattern (full symmetric storage); factorize() reuses it as long
  // as the pattern stays the same. Auto picks the backend here, by A's size.
  void analyze(const Matrix& A);
  // Numeric factorization; false when A is not positive definite.
  bool factorize(const Matrix& A);
  // Solve with a float32 copy of the supernodal factor (CHOLMOD's or ours, made by the next
  // factorize): half the bytes, relative error ~1e-7, for preconditioners. The Eigen backend
  // ignores it.
  void set_single_precision_solve(bool single);
  // x = A^-1 b with the last factorization.
  void solve(const Vec& b, Vec& x) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace corotate
