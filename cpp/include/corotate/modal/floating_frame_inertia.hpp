// The inertia of a modal body that moves as a whole: a floating frame (origin p, rotation R)
// carrying the reduced deformation, node i at p + R u_i with u_i = X_i + Psi_i zeta (X the
// rest positions in the frame, Psi the modal basis, zeta the modal coordinates).
//
// Velocities are taken in the frame ("quasi-velocities"): w = (v, omega, eta) with
// p' = R v, R' = R [omega]x, zeta' = eta. Node i then moves at R (v - [u_i]x omega + Psi_i eta),
// and the kinetic energy with the consistent mass (m_ij I per node pair: the isotropic mass of
// every solid element) is T = 1/2 w^T M(zeta) w, with
//
//   M = [ m I        -[c]x       A     ]     c = sum m_ij u_j        (first moment)
//       [ [c]x        J          B     ]     J = sum m_ij [u_i]x^T [u_j]x   (inertia tensor)
//       [ A^T         B^T        M_r   ]     B = sum m_ij [u_i]x Psi_j      A = sum m_ij Psi_j
//
// Everything in M is a sum over pairs of the fields F_0 = X, F_k = Psi_k (mode k) weighted by
// m_ij, so it follows from the (r + 1)^2 3 x 3 moments Q_pq = sum m_ij F_p,i F_q,j^T and the
// first moments s_p = sum m_ij F_p,j, computed once from the mesh (Shabana's inertia
// invariants, in this compact form): with u = F_0 + sum zeta_k F_k, J = tr(Q_uu) I - Q_uu^T
// and column l of B is the axial vector of Q_ul. A step then costs O(r^2), independent of
// the mesh.
//
// The equations of motion (Boltzmann-Hamel, with the momenta pi = M w):
//   pi_v'   + omega x pi_v                = F_ext        (forces in the frame)
//   pi_w'   + omega x pi_w + v x pi_v     = tau_ext      (moments about the origin, in the frame)
//   pi_eta' - dT/dzeta                    = Q_ext - K_r zeta - D_r eta
// so M w' = (external and elastic forces) - M' w - (the gyroscopic terms) + dT/dzeta: the
// velocity-dependent part is quadratic_velocity_forces().
#pragma once

#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

class FloatingFrameInertia {
 public:
  using Matrix = Eigen::MatrixXd;

  // X: rest positions (3 x n) in the frame; node_mass: the consistent mass per node pair
  // (n x n, symmetric: M = node_mass kron I3); basis: 3n x r (DOF 3 i + axis). Throws
  // InvalidInput on mismatched sizes or non-finite values.
  FloatingFrameInertia(const Nodes& X, const Eigen::SparseMatrix<double>& node_mass, const Matrix& basis);

  Index num_modes() const { return r_; }
  double mass() const { return mass_; }
  // The reduced mass Psi^T M Psi (r x r).
  const Matrix& modal_mass() const { return modal_mass_; }

  // M(zeta), (6 + r) square, into M (sized on first use).
  void mass_matrix(const Vec& zeta, Matrix& M) const;
  // The momenta pi = M(zeta) w (6 + r) without forming M (a step's residual needs no more).
  void momenta(const Vec& zeta, const Vec& w, Vec& pi) const;
  // The velocity-dependent forces f with M w' = f + (applied and elastic forces): the
  // gyroscopic terms of the frame, -M'(zeta, eta) w and dT/dzeta.
  void quadratic_velocity_forces(const Vec& zeta, const Vec& w, Vec& f) const;
  // dT/dzeta at (zeta, w): the modal coordinates' share of the velocity-dependent forces.
  void kinetic_energy_gradient(const Vec& zeta, const Vec& w, Vec& gradient) const;
  // The derivatives the implicit step's Jacobian needs, at (zeta, w): d(M(zeta) w)/dzeta
  // ((6 + r) x r), and of dT/dzeta by w (r x (6 + r)) and by zeta (r x r). M is affine in zeta
  // but for J (quadratic), and dT/dzeta quadratic in w: all follow from the moments Q_pq.
  void velocity_derivatives(const Vec& zeta, const Vec& w, Matrix& dmomentum_dzeta, Matrix& dgradient_dw,
                            Matrix& dgradient_dzeta) const;
  // A's column k: sum m_ij Psi_k at node j (mode k's first moment; the modal load of a
  // uniform acceleration a in the frame is -a . A_k).
  const Vec3& modal_first_moment(Index k) const { return first_[k + 1]; }
  // The frame-fixed first moment c(zeta) and inertia tensor J(zeta) about the origin.
  Vec3 first_moment(const Vec& zeta) const;
  Mat3 inertia(const Vec& zeta) const;

 private:
  // The moments for u (a = (1, zeta)) against every field into u_moments_, and Q_uu.
  void moments_of(const Vec& zeta, Mat3& uu) const;
  const Mat3& Q(Index p, Index q) const { return moments_[p * (r_ + 1) + q]; }
  void check_sizes(const Vec& zeta, const Vec& w) const;
  // u_moments_rate_ (and Q_{u'u}) along eta, after moments_of.
  void moment_rates(const Vec& zeta, const Eigen::Ref<const Vec>& eta, Mat3& rate_uu) const;
  // rate_axial_ (3 r: axial(Q_{u'k}) at 3 k) along eta.
  void rate_axials(const Eigen::Ref<const Vec>& eta) const;
  // dT/dzeta from u_moments_ and rate_axial_.
  void energy_gradient(const Vec3& v, const Vec3& omega, Vec& out) const;

  Index r_ = 0;
  double mass_ = 0.0;
  std::vector<Mat3> moments_;  // (r + 1)^2 of them, row p, column q
  std::vector<Vec3> first_;    // s_p
  Matrix modal_mass_;
  // The same moments laid out for matrix-vector products (vectorised, a step's hot path):
  // moment_base_ stacks vec(Q_0q) over q, column k of moment_columns_ stacks vec(Q_{k+1,q}),
  // so the u-moments are moment_base_ + moment_columns_ zeta and their rates
  // moment_columns_ eta. For the Jacobian, r x r tables of the modal moments Q_{k+1,l+1}: the
  // three components of their axial vectors, their traces, and their symmetric parts' six
  // entries (xx, yy, zz, xy, xz, yz).
  Vec moment_base_;
  Matrix moment_columns_;
  std::array<Matrix, 3> modal_axial_;
  Matrix modal_axial_rows_;  // (3 l + a, k): axial(Q_{k+1,l+1})_a, for rate_axials' product
  Matrix modal_trace_;
  std::array<Matrix, 6> modal_symmetric_;
  // Work space of the const members (a step allocates nothing after the first).
  mutable std::vector<Mat3> u_moments_, u_moments_rate_;
  mutable Vec gradient_, stacked_, rate_axial_;
  mutable Vec cached_zeta_;  // moments_of's last zeta (empty: none): u_moments_, cached_uu_ are its
  mutable Mat3 cached_uu_ = Mat3::Zero();
  mutable Matrix table_;  // velocity_derivatives' omega-weighted combination of the tables
};

}  // namespace corotate
