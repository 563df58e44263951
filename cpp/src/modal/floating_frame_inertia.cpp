#include "corotate/modal/floating_frame_inertia.hpp"

#include <cmath>
#include <string>

#include "corotate/materials/determinant_derivatives.hpp"  // cross_matrix
#include "corotate/modal/inertial_load_cases.hpp"           // kSymmetricPairs

namespace corotate {

namespace {

// The axial vector of P's antisymmetric part: sum m_ij a_i x b_j for P = sum m_ij a_i b_j^T.
Vec3 axial(const Mat3& P) { return Vec3(P(1, 2) - P(2, 1), P(2, 0) - P(0, 2), P(0, 1) - P(1, 0)); }

// sum m_ij [a_i]x^T [b_j]x for P = sum m_ij a_i b_j^T: tr(P) I - P^T.
Mat3 cross_inertia(const Mat3& P) { return P.trace() * Mat3::Identity() - P.transpose(); }

}  // namespace

FloatingFrameInertia::FloatingFrameInertia(const Nodes& X, const Eigen::SparseMatrix<double>& node_mass,
                                           const Matrix& basis) {
  const Index n = X.cols();
  if (node_mass.rows() != n || node_mass.cols() != n)
    throw InvalidInput("floating frame: the node mass matrix must be " + std::to_string(n) + " x " + std::to_string(n) +
                       " (one row per node)");
  if (basis.rows() != 3 * n)
    throw InvalidInput("floating frame: the basis must have 3n = " + std::to_string(3 * n) + " rows, got " +
                       std::to_string(basis.rows()));
  if (!X.allFinite() || !basis.allFinite())
    throw InvalidInput("floating frame: the rest positions and the basis must be finite");
  r_ = basis.cols();
  const Index fields = r_ + 1;
  // Field p of node i: F_0 = X_i, F_k = Psi_k at node i.
  auto field = [&](Index p, Index i) -> Vec3 {
    return p == 0 ? Vec3(X.col(i)) : Vec3(basis.block<3, 1>(3 * i, p - 1));
  };
  moments_.assign(fields * fields, Mat3::Zero());
  first_.assign(fields, Vec3::Zero());
  Eigen::Matrix<double, 3, Eigen::Dynamic> left(3, fields), right(3, fields);
  for (Index j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(node_mass, j); it; ++it) {
      const Index i = it.row();
      const double m = it.value();
      if (!std::isfinite(m)) throw InvalidInput("floating frame: the node mass matrix must be finite");
      mass_ += m;
      for (Index p = 0; p < fields; ++p) left.col(p) = field(p, i), right.col(p) = field(p, j);
      for (Index p = 0; p < fields; ++p) {
        first_[p] += m * right.col(p);
        for (Index q = 0; q < fields; ++q) moments_[p * fields + q] += m * left.col(p) * right.col(q).transpose();
      }
    }
  if (!(mass_ > 0.0)) throw InvalidInput("floating frame: the body's mass must be positive");
  modal_mass_.resize(r_, r_);
  for (Index k = 0; k < r_; ++k)
    for (Index l = 0; l < r_; ++l) modal_mass_(k, l) = Q(k + 1, l + 1).trace();
  moment_base_.resize(9 * fields);
  moment_columns_.resize(9 * fields, r_);
  for (Index q = 0; q < fields; ++q) {
    moment_base_.segment<9>(9 * q) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(Q(0, q).data());
    for (Index k = 0; k < r_; ++k)
      moment_columns_.block<9, 1>(9 * q, k) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(Q(k + 1, q).data());
  }
  modal_axial_rows_.resize(3 * r_, r_);
  for (auto& m : modal_axial_) m.resize(r_, r_);
  for (auto& m : modal_symmetric_) m.resize(r_, r_);
  modal_trace_.resize(r_, r_);
  for (Index k = 0; k < r_; ++k)
    for (Index l = 0; l < r_; ++l) {
      const Mat3& Qkl = Q(k + 1, l + 1);
      const Vec3 ax = axial(Qkl);
      for (int a = 0; a < 3; ++a) modal_axial_[a](k, l) = ax[a], modal_axial_rows_(3 * l + a, k) = ax[a];
      modal_trace_(k, l) = Qkl.trace();
      for (int p = 0; p < 6; ++p) {
        const int a = kSymmetricPairs[p][0], b = kSymmetricPairs[p][1];
        modal_symmetric_[p](k, l) = 0.5 * (Qkl(a, b) + Qkl(b, a));
      }
    }
}

void FloatingFrameInertia::moments_of(const Vec& zeta, Mat3& uu) const {
  // One matrix-vector product, skipped when zeta is the last one's (a step's balance, its dT/dzeta
  // and its Jacobian ask for the same zeta).
  const Index fields = r_ + 1;
  if (cached_zeta_.size() == zeta.size() && cached_zeta_ == zeta) {
    uu = cached_uu_;
    return;
  }
  stacked_.noalias() = moment_columns_ * zeta;
  stacked_ += moment_base_;
  u_moments_.resize(fields);
  uu = Eigen::Map<const Mat3>(stacked_.data());
  u_moments_[0] = uu;
  for (Index q = 1; q < fields; ++q) {
    u_moments_[q] = Eigen::Map<const Mat3>(stacked_.data() + 9 * q);
    uu += zeta[q - 1] * u_moments_[q];
  }
  cached_zeta_ = zeta;
  cached_uu_ = uu;
}

Vec3 FloatingFrameInertia::first_moment(const Vec& zeta) const {
  Vec3 c = first_[0];
  for (Index k = 0; k < r_; ++k) c += zeta[k] * first_[k + 1];
  return c;
}

Mat3 FloatingFrameInertia::inertia(const Vec& zeta) const {
  Mat3 uu;
  moments_of(zeta, uu);
  return cross_inertia(uu);
}

void FloatingFrameInertia::mass_matrix(const Vec& zeta, Matrix& M) const {
  if (zeta.size() != r_) throw InvalidInput("floating frame: " + std::to_string(r_) + " modal coordinates expected");
  const Index size = 6 + r_;
  M.resize(size, size);
  Mat3 uu;
  moments_of(zeta, uu);
  const Vec3 c = first_moment(zeta);
  M.setZero();
  M.block<3, 3>(0, 0) = mass_ * Mat3::Identity();
  M.block<3, 3>(0, 3) = -cross_matrix(c);
  M.block<3, 3>(3, 0) = cross_matrix(c);
  M.block<3, 3>(3, 3) = cross_inertia(uu);
  for (Index k = 0; k < r_; ++k) {
    M.block<3, 1>(0, 6 + k) = first_[k + 1];           // A
    M.block<3, 1>(3, 6 + k) = axial(u_moments_[k + 1]);  // B
  }
  M.block(6, 0, r_, 6) = M.block(0, 6, 6, r_).transpose();
  M.bottomRightCorner(r_, r_) = modal_mass_;
}

void FloatingFrameInertia::momenta(const Vec& zeta, const Vec& w, Vec& pi) const {
  check_sizes(zeta, w);
  Mat3 uu;
  moments_of(zeta, uu);
  const Vec3 c = first_moment(zeta), v = w.segment<3>(0), omega = w.segment<3>(3);
  const auto eta = w.tail(r_);
  pi.resize(6 + r_);
  Vec3 A_eta = Vec3::Zero(), B_eta = Vec3::Zero();
  for (Index k = 0; k < r_; ++k) {
    const Vec3 B_k = axial(u_moments_[k + 1]);
    A_eta += eta[k] * first_[k + 1];
    B_eta += eta[k] * B_k;
    pi[6 + k] = first_[k + 1].dot(v) + B_k.dot(omega);
  }
  pi.segment<3>(0) = mass_ * v - c.cross(omega) + A_eta;
  pi.segment<3>(3) = c.cross(v) + cross_inertia(uu) * omega + B_eta;
  pi.tail(r_).noalias() += modal_mass_ * eta;
}

void FloatingFrameInertia::check_sizes(const Vec& zeta, const Vec& w) const {
  if (zeta.size() != r_ || w.size() != 6 + r_)
    throw InvalidInput("floating frame: " + std::to_string(r_) + " modal coordinates and " + std::to_string(6 + r_) +
                       " velocities expected");
}

void FloatingFrameInertia::moment_rates(const Vec& zeta, const Eigen::Ref<const Vec>& eta, Mat3& rate_uu) const {
  // Rates along zeta' = eta: Q_{u'q} = sum_k eta_k Q_kq, Q_{u'u} = sum_q a_q Q_{u'q}.
  const Index fields = r_ + 1;
  stacked_.noalias() = moment_columns_ * eta;
  u_moments_rate_.resize(fields);
  rate_uu = Eigen::Map<const Mat3>(stacked_.data());
  u_moments_rate_[0] = rate_uu;
  for (Index q = 1; q < fields; ++q) {
    u_moments_rate_[q] = Eigen::Map<const Mat3>(stacked_.data() + 9 * q);
    rate_uu += zeta[q - 1] * u_moments_rate_[q];
  }
}

void FloatingFrameInertia::rate_axials(const Eigen::Ref<const Vec>& eta) const {
  // axial(Q_{u'k}) = sum_l eta_l axial(Q_lk) for every mode k: one product with the modal
  // axial table, a third of moment_rates' work (the rest of the rates is not needed there).
  rate_axial_.noalias() = modal_axial_rows_ * eta;
}

void FloatingFrameInertia::energy_gradient(const Vec3& v, const Vec3& omega, Vec& out) const {
  // dT/dzeta_k = -v . (A_k x omega) + tr(Q_uk) |omega|^2 - omega^T Q_uk omega + omega^T dB/dzeta_k eta,
  // the last omega . axial(sum_l eta_l Q_kl) = -omega . axial(Q_{u'k}) (Q_lk = Q_kl^T).
  const double omega2 = omega.squaredNorm();
  for (Index k = 0; k < r_; ++k) {
    const Mat3& Quk = u_moments_[k + 1];
    out[k] = -v.dot(first_[k + 1].cross(omega)) + Quk.trace() * omega2 - omega.dot(Quk * omega) -
             omega.dot(rate_axial_.segment<3>(3 * k));
  }
}

void FloatingFrameInertia::kinetic_energy_gradient(const Vec& zeta, const Vec& w, Vec& gradient) const {
  check_sizes(zeta, w);
  Mat3 uu;
  moments_of(zeta, uu);
  rate_axials(w.tail(r_));
  gradient.resize(r_);
  energy_gradient(w.segment<3>(0), w.segment<3>(3), gradient);
}

void FloatingFrameInertia::velocity_derivatives(const Vec& zeta, const Vec& w, Matrix& dmomentum_dzeta,
                                                Matrix& dgradient_dw, Matrix& dgradient_dzeta) const {
  check_sizes(zeta, w);
  const Vec3 v = w.segment<3>(0), omega = w.segment<3>(3);
  const double omega2 = omega.squaredNorm();
  Mat3 uu;
  moments_of(zeta, uu);
  rate_axials(w.tail(r_));
  dmomentum_dzeta.resize(6 + r_, r_);
  dgradient_dw.resize(r_, 6 + r_);
  dgradient_dzeta.resize(r_, r_);
  for (Index k = 0; k < r_; ++k) {
    const Vec3& s = first_[k + 1];
    const Mat3& Quk = u_moments_[k + 1];
    const Mat3 symmetric = Quk + Quk.transpose();  // dQ_uu/dzeta_k
    // M w = (m v - c x omega + A eta, c x v + J omega + B eta, A^T v + B^T omega + M_r eta), with
    // dc = s_k, dJ = cross_inertia(dQ_uu), d(B eta) = axial(sum_l eta_l Q_kl) = -axial(Q_{u'k}),
    // d(B^T omega)_l = omega . axial(Q_kl).
    dmomentum_dzeta.block<3, 1>(0, k) = -s.cross(omega);
    dmomentum_dzeta.block<3, 1>(3, k) = s.cross(v) + cross_inertia(symmetric) * omega - rate_axial_.segment<3>(3 * k);
    // dT/dzeta_k = -v . (s_k x omega) + tr(Q_uk) |omega|^2 - omega^T Q_uk omega - omega . axial(Q_{u'k}).
    dgradient_dw.block<1, 3>(k, 0) = -s.cross(omega).transpose();
    dgradient_dw.block<1, 3>(k, 3) =
        (s.cross(v) + 2.0 * Quk.trace() * omega - symmetric * omega - rate_axial_.segment<3>(3 * k)).transpose();
  }
  // The modal rows, from the precomputed tables: (6 + l, k) = omega . axial(Q_kl),
  // dgradient_dw(k, 6 + l) = -omega . axial(Q_lk), dgradient_dzeta(k, l) = tr(Q_lk) |omega|^2 -
  // omega^T Q_lk omega (only Q_lk's symmetric part counts there).
  table_.noalias() = omega[0] * modal_axial_[0];
  table_.noalias() += omega[1] * modal_axial_[1];
  table_.noalias() += omega[2] * modal_axial_[2];
  dmomentum_dzeta.bottomRows(r_) = table_.transpose();
  dgradient_dw.rightCols(r_) = -table_.transpose();
  table_.noalias() = omega2 * modal_trace_;
  table_.noalias() -= (omega[0] * omega[0]) * modal_symmetric_[0];
  table_.noalias() -= (omega[1] * omega[1]) * modal_symmetric_[1];
  table_.noalias() -= (omega[2] * omega[2]) * modal_symmetric_[2];
  table_.noalias() -= (2.0 * omega[0] * omega[1]) * modal_symmetric_[3];
  table_.noalias() -= (2.0 * omega[0] * omega[2]) * modal_symmetric_[4];
  table_.noalias() -= (2.0 * omega[1] * omega[2]) * modal_symmetric_[5];
  dgradient_dzeta = table_.transpose();
}

void FloatingFrameInertia::quadratic_velocity_forces(const Vec& zeta, const Vec& w, Vec& f) const {
  check_sizes(zeta, w);
  const Vec3 v = w.segment<3>(0), omega = w.segment<3>(3);
  const auto eta = w.tail(r_);
  Mat3 uu, rate_uu;
  moments_of(zeta, uu);
  moment_rates(zeta, eta, rate_uu);
  rate_axials(eta);
  const Vec3 c = first_moment(zeta);
  Vec3 c_rate = Vec3::Zero(), B_eta = Vec3::Zero(), B_rate_eta = Vec3::Zero();
  for (Index k = 0; k < r_; ++k) {
    c_rate += eta[k] * first_[k + 1];  // (also A eta)
    B_eta += eta[k] * axial(u_moments_[k + 1]);
    B_rate_eta += eta[k] * rate_axial_.segment<3>(3 * k);
  }
  const Mat3 J = cross_inertia(uu);
  const Mat3 J_rate = 2.0 * rate_uu.trace() * Mat3::Identity() - (rate_uu + rate_uu.transpose());
  const Vec3 pi_v = mass_ * v - c.cross(omega) + c_rate;
  const Vec3 pi_w = c.cross(v) + J * omega + B_eta;
  f.resize(6 + r_);
  f.segment<3>(0) = c_rate.cross(omega) - omega.cross(pi_v);
  f.segment<3>(3) = -(c_rate.cross(v) + J_rate * omega + B_rate_eta) - omega.cross(pi_w) - v.cross(pi_v);
  auto modal = f.tail(r_);
  Vec& gradient = gradient_;
  gradient.resize(r_);
  energy_gradient(v, omega, gradient);
  for (Index k = 0; k < r_; ++k) modal[k] = -omega.dot(rate_axial_.segment<3>(3 * k)) + gradient[k];  // -B'^T omega
}

}  // namespace corotate
