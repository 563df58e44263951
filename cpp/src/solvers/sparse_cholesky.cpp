#include "corotate/solvers/sparse_cholesky.hpp"

#include <Eigen/SparseCholesky>

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

// x = A^-1 b from the supernodal factor P A P^T = L L^T: the two triangular sweeps over the
// supernodes with Eigen's dense kernels. cholmod_solve does the same through BLAS (dtrsv,
// dgemv), which Debian's reference BLAS runs as unvectorised loops (15 % of a step at
// 122,880 tets), and allocates its result on every call. work: n + the tallest supernode.
template <typename Scalar>
void supernodal_solve(const cholmod_factor& L, const Scalar* values, const Vec& b, Vec& x,
                      Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& y, Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& gathered) {
  using Panel = Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>, 0, Eigen::OuterStride<>>;
  const Index n = static_cast<Index>(L.n);
  const int* perm = static_cast<const int*>(L.Perm);
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  const int* px = static_cast<const int*>(L.px);
  const int* rows = static_cast<const int*>(L.s);
  const Index supernodes = static_cast<Index>(L.nsuper);
  y.resize(n);
  gathered.resize(static_cast<Index>(L.maxesize));
  for (Index k = 0; k < n; ++k) y[k] = static_cast<Scalar>(b[perm[k]]);
  for (Index s = 0; s < supernodes; ++s) {  // L y' = y
    const int first = super[s], cols = super[s + 1] - first, height = pi[s + 1] - pi[s], below = height - cols;
    const Panel panel(values + px[s], height, cols, Eigen::OuterStride<>(height));
    auto ys = y.segment(first, cols);
    panel.topRows(cols).template triangularView<Eigen::Lower>().solveInPlace(ys);
    if (below == 0) continue;
    auto update = gathered.head(below);
    update.noalias() = panel.bottomRows(below) * ys;
    const int* below_rows = rows + pi[s] + cols;
    for (int r = 0; r < below; ++r) y[below_rows[r]] -= update[r];
  }
  for (Index s = supernodes - 1; s >= 0; --s) {  // L^T y' = y
    const int first = super[s], cols = super[s + 1] - first, height = pi[s + 1] - pi[s], below = height - cols;
    const Panel panel(values + px[s], height, cols, Eigen::OuterStride<>(height));
    auto ys = y.segment(first, cols);
    if (below > 0) {
      auto known = gathered.head(below);
      const int* below_rows = rows + pi[s] + cols;
      for (int r = 0; r < below; ++r) known[r] = y[below_rows[r]];
      ys.noalias() -= panel.bottomRows(below).transpose() * known;
    }
    panel.topRows(cols).template triangularView<Eigen::Lower>().transpose().solveInPlace(ys);
  }
  x.resize(n);
  for (Index k = 0; k < n; ++k) x[perm[k]] = y[k];
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
  Vec permuted, gathered;  // work of supernodal_solve
  bool single = false;               // set_single_precision_solve
  std::vector<float> single_values;  // float copy of the factor's values (made by factorize)
  Eigen::VectorXf permuted_single, gathered_single;
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
    const bool readable =
        L->is_super && L->is_ll && L->itype == CHOLMOD_INT && L->xtype == CHOLMOD_REAL && L->dtype == CHOLMOD_DOUBLE;
    if (!readable) {
      x = impl_->cholmod.solve(b);  // not a form supernodal_solve reads (not expected)
    } else if (impl_->single && impl_->single_values.size() == L->xsize) {
      supernodal_solve(*L, impl_->single_values.data(), b, x, impl_->permuted_single, impl_->gathered_single);
    } else {
      supernodal_solve(*L, static_cast<const double*>(L->x), b, x, impl_->permuted, impl_->gathered);
    }
    return;
  }
#endif
  x = impl_->ldlt.solve(b);
}

}  // namespace corotate
