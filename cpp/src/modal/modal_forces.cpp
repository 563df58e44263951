#include "corotate/modal/modal_forces.hpp"

#include <string>

namespace corotate {

namespace {

void check_finite(const Eigen::MatrixXd& m, const char* what) {
  if (!m.allFinite()) throw InvalidInput(std::string(what) + " has non-finite entries");
}

}  // namespace

ModalForces::ModalForces(const Mat& stiffness, const Mat& quadratic, const Mat& cubic) : K0_(stiffness) {
  const Index r = stiffness.rows();
  if (r < 1 || stiffness.cols() != r) throw InvalidInput("modal stiffness must be a square r x r matrix, r >= 1");
  check_finite(stiffness, "modal stiffness");
  if ((stiffness - stiffness.transpose()).cwiseAbs().maxCoeff() > 1e-10 * stiffness.cwiseAbs().maxCoeff())
    throw InvalidInput("modal stiffness must be symmetric");
  K0_ = 0.5 * (stiffness + stiffness.transpose());
  K_ = K0_;
  if (quadratic.size() != 0) {
    if (quadratic.rows() != r * r || quadratic.cols() != r)
      throw InvalidInput("quadratic modal force tensor must be (r*r) x r for r = " + std::to_string(r));
    check_finite(quadratic, "quadratic modal force tensor");
    // Symmetrise T(l, k, i) = (A_i)_lk in (k, i): f_l = 1/2 sum_ik T(l,k,i) q_k q_i is unchanged.
    A_.resize(r * r, r);
    for (Index i = 0; i < r; ++i)
      for (Index k = 0; k < r; ++k)
        for (Index l = 0; l < r; ++l) A_(l + r * k, i) = 0.5 * (quadratic(l + r * k, i) + quadratic(l + r * i, k));
  }
  if (cubic.size() != 0) {
    if (cubic.rows() != r * r || cubic.cols() != r * r)
      throw InvalidInput("cubic modal force tensor must be (r*r) x (r*r) for r = " + std::to_string(r));
    check_finite(cubic, "cubic modal force tensor");
    // Symmetrise U(l, k, i, j) = (B_ij)_lk over (k, i, j): f_l is unchanged.
    B_.resize(r * r, r * r);
    auto U = [&](Index l, Index k, Index i, Index j) { return cubic(l + r * k, i + r * j); };
    for (Index j = 0; j < r; ++j)
      for (Index i = 0; i < r; ++i)
        for (Index k = 0; k < r; ++k)
          for (Index l = 0; l < r; ++l)
            B_(l + r * k, i + r * j) =
                (U(l, k, i, j) + U(l, k, j, i) + U(l, i, k, j) + U(l, i, j, k) + U(l, j, k, i) + U(l, j, i, k)) / 6.0;
  }
  S1_ = Mat::Zero(r, r);
  S2_ = Mat::Zero(r, r);
  qq_ = Vec::Zero(r * r);
}

void ModalForces::set_load_stiffness(const Mat& extra) {
  if (extra.rows() != size() || extra.cols() != size())
    throw InvalidInput("load stiffness must be " + std::to_string(size()) + " x " + std::to_string(size()));
  check_finite(extra, "load stiffness");
  K_ = K0_ + 0.5 * (extra + extra.transpose());
}

void ModalForces::contract(const Vec& q) {
  const Index r = size();
  if (has_quadratic()) Eigen::Map<Vec>(S1_.data(), r * r).noalias() = A_ * q;
  if (has_cubic()) {
    for (Index j = 0; j < r; ++j) qq_.segment(r * j, r) = q * q[j];
    Eigen::Map<Vec>(S2_.data(), r * r).noalias() = B_ * qq_;
  }
}

void ModalForces::evaluate(const Vec& q, Vec& f, Mat* tangent) {
  if (q.size() != size()) throw InvalidInput("modal coordinates have the wrong size");
  f.resize(size());
  f.noalias() = -K_ * q;
  if (tangent) *tangent = K_;
  if (is_linear()) return;
  contract(q);
  if (has_quadratic()) {
    f.noalias() -= 0.5 * S1_ * q;
    if (tangent) *tangent += S1_;
  }
  if (has_cubic()) {
    f.noalias() -= (1.0 / 3.0) * S2_ * q;
    if (tangent) *tangent += S2_;
  }
}

double ModalForces::energy(const Vec& q) {
  if (q.size() != size()) throw InvalidInput("modal coordinates have the wrong size");
  double e = 0.5 * q.dot(K_ * q);
  if (is_linear()) return e;
  contract(q);
  if (has_quadratic()) e += q.dot(S1_ * q) / 6.0;
  if (has_cubic()) e += q.dot(S2_ * q) / 12.0;
  return e;
}

}  // namespace corotate
