#include "corotate/solvers/sparse_cholesky.hpp"

#include <Eigen/SparseCholesky>

#include "corotate/solvers/supernodal_solve.hpp"

#ifdef COROTATE_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

namespace corotate {

#ifdef COROTATE_HAVE_CHOLMOD
namespace {

// CHOLMOD's supernodal factor, with access to its arrays for our own solve.
struct SupernodalLLT : Eigen::CholmodSupernodalLLT<SparseCholesky::Matrix, Eigen::Lower> {
  const cholmod_factor* factor() const { return m_cholmodFactor; }
};

// Whether supernodal_solve reads this factor (a supernodal LL^T of doubles, int indices).
bool readable(const cholmod_factor& L) {
  return L.is_super && L.is_ll && L.itype == CHOLMOD_INT && L.xtype == CHOLMOD_REAL && L.dtype == CHOLMOD_DOUBLE;
}

// supernodal_solve.hpp's view of CHOLMOD's supernodal factor.
SupernodalFactor view_of(const cholmod_factor& L) {
  SupernodalFactor f;
  f.n = static_cast<Index>(L.n);
  f.nsuper = static_cast<Index>(L.nsuper);
  f.perm = static_cast<const int*>(L.Perm);
  f.super = static_cast<const int*>(L.super);
  f.pi = static_cast<const int*>(L.pi);
  f.px = static_cast<const int*>(L.px);
  f.rows = static_cast<const int*>(L.s);
  return f;
}

}  // namespace
#endif

struct SparseCholesky::Impl {
  Backend backend = Backend::Auto;
  bool analysed = false;
  bool use_cholmod = false;
  Eigen::SimplicialLDLT<Matrix> ldlt;
#ifdef COROTATE_HAVE_CHOLMOD
  SupernodalLLT cholmod;
  SupernodalFactor view;   // of the last factorization
  SupernodalSplit split;   // for two threads
  SupernodalWork<double> work;
  bool single = false;               // set_single_precision_solve
  std::vector<float> single_values;  // float copy of the factor's values (made by factorize)
  SupernodalWork<float> work_single;
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

void SparseCholesky::set_single_precision_solve(bool single) {
#ifdef COROTATE_HAVE_CHOLMOD
  impl_->single = single;
#endif
}

const char* SparseCholesky::backend_name() const {
  if (impl_->backend == Backend::Auto && !impl_->analysed) return "auto";
  return impl_->use_cholmod ? "cholmod" : "eigen";
}

void SparseCholesky::analyze(const Matrix& A) {
  if (impl_->backend == Backend::Auto) impl_->use_cholmod = have_cholmod() && A.rows() >= kCholmodFromDofs;
  if (impl_->backend == Backend::Cholmod) impl_->use_cholmod = A.rows() > 0;  // CHOLMOD has no empty factor
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
    if (impl_->cholmod.info() != Eigen::Success) return false;
    if (readable(*impl_->cholmod.factor())) {
      impl_->view = view_of(*impl_->cholmod.factor());
      impl_->split = SupernodalSplit::of(impl_->view);
    }
    if (impl_->single) {
      const cholmod_factor* L = impl_->cholmod.factor();
      const double* v = static_cast<const double*>(L->x);
      impl_->single_values.assign(v, v + L->xsize);
    }
    return true;
  }
#endif
  impl_->ldlt.factorize(A);
  return impl_->ldlt.info() == Eigen::Success && (impl_->ldlt.vectorD().array() > 0).all();
}

void SparseCholesky::solve(const Vec& b, Vec& x) const {
#ifdef COROTATE_HAVE_CHOLMOD
  if (impl_->use_cholmod) {
    const cholmod_factor* L = impl_->cholmod.factor();
    if (!readable(*L)) {
      x = impl_->cholmod.solve(b);  // not a form supernodal_solve reads (not expected)
    } else if (impl_->single && impl_->single_values.size() == L->xsize) {
      supernodal_solve(impl_->view, impl_->split, impl_->single_values.data(), b, x, impl_->work_single);
    } else {
      supernodal_solve(impl_->view, impl_->split, static_cast<const double*>(L->x), b, x, impl_->work);
    }
    return;
  }
#endif
  x = impl_->ldlt.solve(b);
}

}  // namespace corotate
