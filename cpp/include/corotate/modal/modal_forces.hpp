// Internal forces of a reduced (modal) body as a polynomial in the modal coordinates q:
//
//     f(q) = -(K q + 1/2 sum_i q_i A_i q + 1/3 sum_ij q_i q_j B_ij q),
//     T(q) = -df/dq = K + sum_i q_i A_i + sum_ij q_i q_j B_ij.
//
// K is the modal stiffness (diagonal for an orthonormalised basis) plus any load-dependent
// stiffness set by set_load_stiffness (the load-based geometric stiffness, paper eqs 7-8).
// The quadratic term with A_i the modal geometric stiffness of mode i is the paper's
// eq. (11) (mode-based K_sigma, eqs 9-10); the quadratic and cubic terms of a reduced
// St. Venant-Kirchhoff body (Barbic & James 2005) have the same form, with A and B
// precomputed once. The tangent formula holds when A_i q is symmetric in the scaling index
// and the multiplied index (and B in its three last indices): the forces only depend on that
// symmetric part, so the constructor symmetrises the tensors once, without changing f.
//
// Layout: A is (r*r) x r, column i = the r x r matrix A_i stored column-major (row l + r*k
// holds (A_i)_lk); B is (r*r) x (r*r), column i + r*j = B_ij the same way. Empty A or B
// means no such term. evaluate() allocates nothing.
#pragma once

#include "corotate/common.hpp"

namespace corotate {

class ModalForces {
 public:
  using Mat = Eigen::MatrixXd;

  ModalForces(const Mat& stiffness, const Mat& quadratic, const Mat& cubic);

  Index size() const { return K0_.rows(); }
  bool is_linear() const { return A_.size() == 0 && B_.size() == 0; }
  bool has_quadratic() const { return A_.size() != 0; }
  bool has_cubic() const { return B_.size() != 0; }
  const Mat& base_stiffness() const { return K0_; }
  // K0 + the load stiffness: the tangent at q = 0.
  const Mat& stiffness() const { return K_; }
  const Mat& quadratic() const { return A_; }
  const Mat& cubic() const { return B_; }

  // K = K0 + extra (r x r, symmetric, finite): the load-based geometric stiffness.
  void set_load_stiffness(const Mat& extra);

  // f = the internal modal forces at q; tangent (if not null) = -df/dq.
  void evaluate(const Vec& q, Vec& f, Mat* tangent);
  // Elastic energy at q (the potential of f: f = -dE/dq).
  double energy(const Vec& q);

 private:
  void contract(const Vec& q);  // S1_ = sum_i q_i A_i, S2_ = sum_ij q_i q_j B_ij

  Mat K0_, K_, A_, B_;
  Mat S1_, S2_;  // workspace, r x r
  Vec qq_;       // workspace, q (x) q
};

}  // namespace corotate
