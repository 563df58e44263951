#include "corotate/solvers/pcg.hpp"

#include <cmath>

#include "corotate/simd8.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"

#if COROTATE_HAVE_FLOAT8 && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"  // see simd8.hpp
#endif

namespace corotate {

namespace {

// CG's vector operations as loops over vectors of doubles, compiled per instruction set
// (cpu_clones.hpp): Eigen's own run two doubles wide in a build for the x86-64 baseline, and on
// a small body (the Table 1 cage, 900 unknowns) they were 6 % of a step. Sums run in lanes,
// added at the end (another order than Eigen's: the same to round-off). Eight-double vectors
// on the AVX-512 path, four-double ones elsewhere (simd8.hpp says why).
#if COROTATE_HAVE_FLOAT8
using simd::Double4;
using simd::Double8;
using simd::load;
using simd::store;

template <class V>
constexpr Index kLanes = sizeof(V) / sizeof(double);

// a . b
template <class V>
COROTATE_CLONE_INLINE double dot_with(const Vec& a, const Vec& b) {
  constexpr Index w = kLanes<V>;
  const Index n = a.size();
  const double *pa = a.data(), *pb = b.data();
  V s0 = {}, s1 = {};
  Index i = 0;
  for (; i + 2 * w <= n; i += 2 * w) {
    s0 += load<V>(pa + i) * load<V>(pb + i);
    s1 += load<V>(pa + i + w) * load<V>(pb + i + w);
  }
  double s = simd::sum(s0 + s1);
  for (; i < n; ++i) s += pa[i] * pb[i];
  return s;
}

// r = b - r (r holding A x); returns r . r.
template <class V>
COROTATE_CLONE_INLINE double residual_with(const Vec& b, Vec& r) {
  constexpr Index w = kLanes<V>;
  const Index n = b.size();
  const double* pb = b.data();
  double* pr = r.data();
  V s8 = {};
  Index i = 0;
  for (; i + w <= n; i += w) {
    const V v = load<V>(pb + i) - load<V>(pr + i);
    store<V>(pr + i, v);
    s8 += v * v;
  }
  double s = simd::sum(s8);
  for (; i < n; ++i) {
    pr[i] = pb[i] - pr[i];
    s += pr[i] * pr[i];
  }
  return s;
}

// x += alpha p, r -= alpha q; returns r . r.
template <class V>
COROTATE_CLONE_INLINE double step_with(double alpha, const Vec& p, const Vec& q, Vec& x, Vec& r) {
  constexpr Index w = kLanes<V>;
  const Index n = p.size();
  const double *pp = p.data(), *pq = q.data();
  double *px = x.data(), *pr = r.data();
  V s8 = {};
  Index i = 0;
  for (; i + w <= n; i += w) {
    store<V>(px + i, load<V>(px + i) + alpha * load<V>(pp + i));
    const V v = load<V>(pr + i) - alpha * load<V>(pq + i);
    store<V>(pr + i, v);
    s8 += v * v;
  }
  double s = simd::sum(s8);
  for (; i < n; ++i) {
    px[i] += alpha * pp[i];
    pr[i] -= alpha * pq[i];
    s += pr[i] * pr[i];
  }
  return s;
}

// p = z + beta p
template <class V>
COROTATE_CLONE_INLINE void next_direction_with(const Vec& z, double beta, Vec& p) {
  constexpr Index w = kLanes<V>;
  const Index n = z.size();
  const double* pz = z.data();
  double* pp = p.data();
  Index i = 0;
  for (; i + w <= n; i += w) store<V>(pp + i, load<V>(pz + i) + beta * load<V>(pp + i));
  for (; i < n; ++i) pp[i] = pz[i] + beta * pp[i];
}

COROTATE_CPU_CLONES double dot(const Vec& a, const Vec& b) {
  return cpu_runs_avx512_clones() ? dot_with<Double8>(a, b) : dot_with<Double4>(a, b);
}
COROTATE_CPU_CLONES double residual(const Vec& b, Vec& r) {
  return cpu_runs_avx512_clones() ? residual_with<Double8>(b, r) : residual_with<Double4>(b, r);
}
COROTATE_CPU_CLONES double step(double alpha, const Vec& p, const Vec& q, Vec& x, Vec& r) {
  return cpu_runs_avx512_clones() ? step_with<Double8>(alpha, p, q, x, r) : step_with<Double4>(alpha, p, q, x, r);
}
COROTATE_CPU_CLONES void next_direction(const Vec& z, double beta, Vec& p) {
  cpu_runs_avx512_clones() ? next_direction_with<Double8>(z, beta, p) : next_direction_with<Double4>(z, beta, p);
}
#else
double dot(const Vec& a, const Vec& b) { return a.dot(b); }
double residual(const Vec& b, Vec& r) {
  r = b - r;
  return r.squaredNorm();
}
double step(double alpha, const Vec& p, const Vec& q, Vec& x, Vec& r) {
  x.noalias() += alpha * p;
  r.noalias() -= alpha * q;
  return r.squaredNorm();
}
void next_direction(const Vec& z, double beta, Vec& p) { p = z + beta * p; }
#endif

}  // namespace

void PCGSettings::validate() const {
  if (max_iterations < 1) throw InvalidInput("PCG: max_iterations must be at least 1");
  if (!(tolerance >= 0) || !std::isfinite(tolerance))
    throw InvalidInput("PCG: tolerance must be positive (or 0 for the preconditioner's default)");
}

PCG::PCG(const PCGSettings& settings)
    : settings_(settings), preconditioner_(make_preconditioner(settings.preconditioner)) {
  settings.validate();
  preconditioner_->set_single_precision_products(settings.single_precision_products());
}

void PCG::precondition() {
  if (fixed_dofs_.empty()) {
    preconditioner_->apply(r_, z_);
    return;
  }
  // The decoupled fixed rows are identity rows: their residual enters neither the
  // preconditioner nor the free DOFs' correction.
  for (size_t k = 0; k < fixed_dofs_.size(); ++k) {
    fixed_residual_[k] = r_[fixed_dofs_[k]];
    r_[fixed_dofs_[k]] = 0.0;
  }
  preconditioner_->apply(r_, z_);
  for (size_t k = 0; k < fixed_dofs_.size(); ++k) r_[fixed_dofs_[k]] = z_[fixed_dofs_[k]] = fixed_residual_[k];
}

void PCG::multiply(const BlockSparseMatrix* A, const SinglePrecisionSymmetric* single, const Vec& v, Vec& out) const {
  if (single) single->multiply(v, out);
  else A->multiply_symmetric(v, out);
  if (coupling_) coupling_->multiply_add(v, out);
}

SolveStats PCG::solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) {
  if (!fixed_dofs_.empty() && fixed_dofs_.back() >= b.size())
    throw InvalidInput("PCG: the fixed DOFs it was given do not belong to this " + std::to_string(b.size()) +
                       "-DOF system");
  preconditioner_->compute(A);
  const SinglePrecisionSymmetric* single =
      settings_.single_precision_products() ? preconditioner_->single_precision_matrix() : nullptr;
  return iterate(&A, single, b, x);
}

SolveStats PCG::solve_single_precision(const Vec& b, Vec& x) {
  SinglePrecisionSymmetric* single = single_precision_target();
  if (!single) throw InvalidInput("PCG: no float32 system to solve (single_precision_target() is null)");
  if (single->num_nodes() * 3 != b.size() || (!fixed_dofs_.empty() && fixed_dofs_.back() >= b.size()))
    throw InvalidInput("PCG: a right-hand side of " + std::to_string(b.size()) + " entries for a " +
                       std::to_string(3 * single->num_nodes()) + "-DOF float32 system and its fixed DOFs");
  preconditioner_->compute_assembled();
  return iterate(nullptr, single, b, x);
}

SolveStats PCG::iterate(const BlockSparseMatrix* A, const SinglePrecisionSymmetric* single, const Vec& b, Vec& x) {
  const Index n = b.size();
  r_.resize(n);
  z_.resize(n);
  p_.resize(n);
  q_.resize(n);
  if (!settings_.warm_start || x.size() != n) x.setZero(n);

  const double b_norm = b.norm();
  if (!std::isfinite(b_norm))  // also catches entries so large that the norm overflows
    throw SolverFailure("PCG: the right-hand side is not finite or too large to solve in double precision");
  double tolerance = settings_.tolerance_or(preconditioner_->default_tolerance());
  int max_iterations = settings_.max_iterations;
  if (requested_tolerance_ > 0) {  // request_accuracy: this solve only
    tolerance = std::min(tolerance, requested_tolerance_);
    max_iterations = std::max(max_iterations, requested_iterations_);
    requested_tolerance_ = 0;
  }
  if (b_norm == 0) {
    x.setZero();
    return {0, 0.0, true, tolerance};
  }
  const double target = tolerance * b_norm;
  multiply(A, single, x, r_);
  double r_norm = std::sqrt(residual(b, r_));
  // A warm start is taken as it is only when it beats the tolerance a hundredfold. One that
  // merely meets a loose tolerance is last step's answer with its unremoved error, and
  // applying that again is the warm start's lagged force (bench/README.md): with a
  // preconditioner good enough to leave ~1 % behind, a spinning body's zero-iteration steps
  // gained 2 % energy in 12 steps (tests/solvers/test_pcg_follows_rotation.py). One
  // iteration removes most of it.
  if (r_norm <= (settings_.warm_start ? 0.01 : 1.0) * target) return {0, r_norm / b_norm, true, tolerance};

  precondition();
  p_ = z_;
  double rz = dot(r_, z_);
  int it = 0;
  while (it < max_iterations) {
    multiply(A, single, p_, q_);
    const double pq = dot(p_, q_);
    if (!(pq > 0))
      throw NotPositiveDefinite("PCG: the system matrix is not positive definite (p^T A p = " + std::to_string(pq) +
                                ")");
    const double alpha = rz / pq;
    r_norm = std::sqrt(step(alpha, p_, q_, x, r_));
    ++it;
    if (r_norm <= target) break;
    precondition();
    const double rz_new = dot(r_, z_);
    next_direction(z_, rz_new / rz, p_);
    rz = rz_new;
  }
  preconditioner_->solved(r_norm <= target);
  return {it, r_norm / b_norm, r_norm <= target, tolerance};
}

}  // namespace corotate
