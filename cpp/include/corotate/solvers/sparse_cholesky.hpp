// Sparse Cholesky factorization of a symmetric positive definite matrix, for the direct
// solver (Direct(), Newton steps, statics) and the coarse level of the two-level
// preconditioner. SuiteSparse CHOLMOD (supernodal, with the ordering CHOLMOD picks: AMD, or
// METIS where it pays) when the build found it (Debian: libsuitesparse-dev); Eigen's
// SimplicialLDLT (AMD ordering) otherwise, or on request.
#pragma once

#include <Eigen/SparseCore>
#include <memory>

#include "corotate/common.hpp"

namespace corotate {

class SparseCholesky {
 public:
  enum class Backend { Auto, Eigen, Cholmod };  // Auto: CHOLMOD when built with it
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  static bool have_cholmod();
  // Backend::Cholmod in a build without CHOLMOD throws InvalidInput.
  explicit SparseCholesky(Backend backend = Backend::Auto);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  const char* backend_name() const;  // "cholmod" or "eigen"
  // Symbolic analysis of A's pattern (full symmetric storage); factorize() reuses it as long
  // as the pattern stays the same.
  void analyze(const Matrix& A);
  // Numeric factorization; false when A is not positive definite.
  bool factorize(const Matrix& A);
  // x = A^-1 b with the last factorization.
  void solve(const Vec& b, Vec& x) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace corotate
