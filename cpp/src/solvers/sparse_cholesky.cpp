#include "corotate/solvers/sparse_cholesky.hpp"

#include <Eigen/SparseCholesky>

#include "corotate/solvers/supernodal_cholesky.hpp"
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
  Backend backend = Backend::Auto;  // asked for
  Backend chosen = Backend::Auto;   // by the last analysis (never Auto after one)
  Eigen::SimplicialLDLT<Matrix> ldlt;
  SupernodalCholesky supernodal;
  SupernodalSplit supernodal_split;
  SupernodalWork<double> supernodal_work;
  bool single = false;               // set_single_precision_solve
  std::vector<float> single_values;  // float copy of the factor's values (made by factorize)
  SupernodalWork<float> work_single;
#ifdef COROTATE_HAVE_CHOLMOD
  SupernodalLLT cholmod;
  SupernodalFactor view;   // of the last factorization
  SupernodalSplit split;   // for two threads
  SupernodalWork<double> work;
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
#ifdef COROTATE_HAVE_CHOLMOD
  impl_->cholmod.cholmod().print = 0;  // no messages on stderr: an indefinite matrix is our own error
#endif
}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

void SparseCholesky::set_single_precision_solve(bool single) { impl_->single = single; }

const char* SparseCholesky::backend_name() const {
  switch (impl_->chosen == Backend::Auto ? impl_->backend : impl_->chosen) {
    case Backend::Eigen: return "eigen";
    case Backend::Cholmod: return "cholmod";
    case Backend::Supernodal: return "supernodal";
    default: return "auto";
  }
}

void SparseCholesky::analyze(const Matrix& A) {
  Backend chosen = impl_->backend;
  if (chosen == Backend::Auto)
    chosen = A.rows() < kSupernodalFromDofs ? Backend::Eigen : have_cholmod() ? Backend::Cholmod : Backend::Supernodal;
  if (A.rows() == 0) chosen = Backend::Eigen;  // CHOLMOD has no empty factor
  impl_->chosen = chosen;
  switch (chosen) {
#ifdef COROTATE_HAVE_CHOLMOD
    case Backend::Cholmod: return impl_->cholmod.analyzePattern(A);
#endif
    case Backend::Supernodal:
      impl_->supernodal.analyze(A);
      impl_->supernodal_split = SupernodalSplit::of(impl_->supernodal.factor());
      return;
    default: return impl_->ldlt.analyzePattern(A);
  }
}

bool SparseCholesky::factorize(const Matrix& A) {
  switch (impl_->chosen) {
#ifdef COROTATE_HAVE_CHOLMOD
    case Backend::Cholmod: {
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
    case Backend::Supernodal:
      if (!impl_->supernodal.factorize(A)) return false;
      if (impl_->single) {
        const double* v = impl_->supernodal.values();
        impl_->single_values.assign(v, v + impl_->supernodal.num_values());
      }
      return true;
    default:
      impl_->ldlt.factorize(A);
      return impl_->ldlt.info() == Eigen::Success && (impl_->ldlt.vectorD().array() > 0).all();
  }
}

void SparseCholesky::solve(const Vec& b, Vec& x) const {
  switch (impl_->chosen) {
#ifdef COROTATE_HAVE_CHOLMOD
    case Backend::Cholmod: {
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
    case Backend::Supernodal:
      if (impl_->single && impl_->single_values.size() == impl_->supernodal.num_values())
        supernodal_solve(impl_->supernodal.factor(), impl_->supernodal_split, impl_->single_values.data(), b, x,
                         impl_->work_single);
      else
        supernodal_solve(impl_->supernodal.factor(), impl_->supernodal_split, impl_->supernodal.values(), b, x,
                         impl_->supernodal_work);
      return;
    default: x = impl_->ldlt.solve(b);
  }
}

}  // namespace corotate
