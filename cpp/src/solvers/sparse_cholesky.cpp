#include "corotate/solvers/sparse_cholesky.hpp"

#include <Eigen/SparseCholesky>

#ifdef COROTATE_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

namespace corotate {

struct SparseCholesky::Impl {
  Backend backend = Backend::Auto;
  bool analysed = false;
  bool use_cholmod = false;
  Eigen::SimplicialLDLT<Matrix> ldlt;
#ifdef COROTATE_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<Matrix, Eigen::Lower> cholmod;
#endif
};

bool SparseCholesky::have_cholmod() {
#ifdef COROTATE_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

SparseCholesky::SparseCholesky(Backend backend) : impl_(std::make_unique<Impl>()) {
  if (backend == Backend::Cholmod && !have_cholmod())
    throw InvalidInput("CHOLMOD was asked for, but corotate was built without SuiteSparse");
  impl_->backend = backend;
  impl_->use_cholmod = backend == Backend::Cholmod;
#ifdef COROTATE_HAVE_CHOLMOD
  impl_->cholmod.cholmod().print = 0;  // no messages on stderr: an indefinite matrix is our own error
#endif
}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

const char* SparseCholesky::backend_name() const {
  if (impl_->backend == Backend::Auto && !impl_->analysed) return "auto";
  return impl_->use_cholmod ? "cholmod" : "eigen";
}

void SparseCholesky::analyze(const Matrix& A) {
  if (impl_->backend == Backend::Auto) impl_->use_cholmod = have_cholmod() && A.rows() >= kCholmodFromDofs;
  impl_->analysed = true;
#ifdef COROTATE_HAVE_CHOLMOD
  if (impl_->use_cholmod) return impl_->cholmod.analyzePattern(A);
#endif
  impl_->ldlt.analyzePattern(A);
}

bool SparseCholesky::factorize(const Matrix& A) {
#ifdef COROTATE_HAVE_CHOLMOD
  if (impl_->use_cholmod) {
    impl_->cholmod.factorize(A);
    return impl_->cholmod.info() == Eigen::Success;
  }
#endif
  impl_->ldlt.factorize(A);
  return impl_->ldlt.info() == Eigen::Success && (impl_->ldlt.vectorD().array() > 0).all();
}

void SparseCholesky::solve(const Vec& b, Vec& x) const {
#ifdef COROTATE_HAVE_CHOLMOD
  if (impl_->use_cholmod) {
    x = impl_->cholmod.solve(b);
    return;
  }
#endif
  x = impl_->ldlt.solve(b);
}

}  // namespace corotate
