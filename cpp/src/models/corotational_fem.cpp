#include "corotate/models/corotational_fem.hpp"

#include "corotate/models/rotation_extraction.hpp"

namespace corotate {

namespace {
// Linear-tet kernels (see kTetKernel in the header).
// The unrotated small strain sym(R^T F) - I of tet e at positions x.
Mat3 tet_strain(const ElementSet<Tet4>& set, const Mat3& R, Index e, const Nodes& x) {
  const auto& G = set.element(e).centre_gradient;  // 4 x 3, constant on the tet
  const int* nodes = &set.cells()(e, 0);
  Mat3 F = Mat3::Zero();
  for (int a = 0; a < 4; ++a) F.noalias() += x.col(nodes[a]) * G.row(a);
  Mat3 strain = R.transpose() * F;
  strain = 0.5 * (strain + strain.transpose()).eval();
  strain.diagonal().array() -= 1.0;
  return strain;
}

Mat3 linear_stress(const Mat3& strain, double lambda, double mu) {
  Mat3 stress = (2 * mu) * strain;
  stress.diagonal().array() += lambda * strain.trace();
  return stress;
}

void add_tet_forces(const ElementSet<Tet4>& set, const Mat3& R, double lambda, double mu, Index e, const Nodes& x, Nodes& f) {
  const auto& el = set.element(e);
  const auto& G = el.centre_gradient;
  const int* nodes = &set.cells()(e, 0);
  const Mat3 P = el.volume * R * linear_stress(tet_strain(set, R, e, x), lambda, mu);  // f_a = -P dN_a/dX
  for (int a = 0; a < 4; ++a) f.col(nodes[a]).noalias() -= P * G.row(a).transpose();
}

void add_tet_stiffness(const ElementSet<Tet4>& set, const Mat3& R, double lambda, double mu, Index e, double scale,
                       BlockSparseMatrix& A) {
  const auto& el = set.element(e);
  const Eigen::Matrix<double, 3, 4> a = R * el.centre_gradient.transpose();  // rotated gradients
  const double v = scale * el.volume;
  const int* ids = set.block_ids(e);
  for (int i = 0; i < 4; ++i)
    for (int j = i; j < 4; ++j) {
      Mat3 block = (v * lambda) * a.col(i) * a.col(j).transpose() + (v * mu) * a.col(j) * a.col(i).transpose();
      block.diagonal().array() += v * mu * a.col(i).dot(a.col(j));
      A.block(ids[i * 4 + j]) += block;
      if (j != i) A.block(ids[j * 4 + i]) += block.transpose();
    }
}

// Exact tangent of a co-rotated tet. With P(F) = R sigma(sym(R^T F) - I) the element force
// is f_a = -V P g_a (g_a = dN_a/dX), so K_ab = V dP[dF = e_j g_b^T] g_a column by column.
// For the polar rotation R^T F = S stays symmetric, which fixes dR = R [theta]x through
//   (tr(S) I - S) theta = vee(W - W^T),  W = R^T dF,
// and then dP = R ([theta]x sigma + dsigma), dsigma = sigma(sym(W - [theta]x S)).
// Returns false (nothing added) where tr(S) I - S is near singular (inverted elements).
bool add_tet_tangent(const ElementSet<Tet4>& set, const Mat3& R, double lambda, double mu, Index e, const Nodes& x,
                     double scale, BlockSparseMatrix& A) {
  const auto& el = set.element(e);
  const auto& G = el.centre_gradient;
  const int* nodes = &set.cells()(e, 0);
  Mat3 F = Mat3::Zero();
  for (int a = 0; a < 4; ++a) F.noalias() += x.col(nodes[a]) * G.row(a);
  Mat3 S = R.transpose() * F;
  S = 0.5 * (S + S.transpose()).eval();
  Mat3 H = -S;
  H.diagonal().array() += S.trace();
  Eigen::LDLT<Mat3> ldlt(H);
  const double h_min = ldlt.vectorD().minCoeff(), h_max = ldlt.vectorD().maxCoeff();
  if (!(h_min > 1e-8 * h_max)) return false;
  Mat3 strain = S;
  strain.diagonal().array() -= 1.0;
  const Mat3 sigma = linear_stress(strain, lambda, mu);
  const double v = scale * el.volume;
  Eigen::Matrix<double, 12, 12> K;
  for (int b = 0; b < 4; ++b)
    for (int j = 0; j < 3; ++j) {
      const Mat3 W = R.row(j).transpose() * G.row(b);  // R^T (e_j g_b^T)
      const Mat3 skew = W - W.transpose();
      const Vec3 theta = ldlt.solve(Vec3(skew(2, 1), skew(0, 2), skew(1, 0)));
      Mat3 T;  // [theta]x
      T << 0, -theta.z(), theta.y(), theta.z(), 0, -theta.x(), -theta.y(), theta.x(), 0;
      Mat3 d_strain = W - T * S;
      d_strain = 0.5 * (d_strain + d_strain.transpose()).eval();
      const Mat3 dP = R * (T * sigma + linear_stress(d_strain, lambda, mu));
      for (int a = 0; a < 4; ++a) K.block<3, 1>(3 * a, 3 * b + j) = v * dP * G.row(a).transpose();
    }
  K = 0.5 * (K + K.transpose()).eval();  // exact symmetry (the co-rotated tet force is a gradient)
  const int* ids = set.block_ids(e);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) A.block(ids[a * 4 + b]) += K.block<3, 3>(3 * a, 3 * b);
  return true;
}

}  // namespace

template <class E>
CorotationalFEM<E>::CorotationalFEM(const Nodes& rest, const Connectivity& cells, const Material& material)
    : FEModel<E>(rest, cells, material),
      lambda_(material.lame_lambda()),
      mu_(material.lame_mu()),
      rotations_(cells.rows(), Mat3::Identity()),
      warm_start_(cells.rows(), Eigen::Quaterniond::Identity()) {
  if constexpr (kTetKernel) this->elements_.release_stiffness();
}

template <class E>
void CorotationalFEM<E>::update(const Nodes& x) {
  const auto& set = this->elements_;
  for (Index e = 0; e < set.num_elements(); ++e) {
    const Mat3 F = set.gather(x, e) * set.element(e).centre_gradient;
    rotations_[e] = extract_rotation(F, warm_start_[e]);
  }
}

template <class E>
void CorotationalFEM<E>::add_element_forces(Index e, const Nodes& x, Nodes& f) const {
  if constexpr (kTetKernel) {
    add_tet_forces(this->elements_, rotations_[e], lambda_, mu_, e, x, f);
    return;
  } else {
  constexpr int N = E::num_nodes;
  const auto& set = this->elements_;
  const Mat3& R = rotations_[e];
  // Unrotated displacement u = R^T x_e - X_e, element force in that frame -K u, rotated back.
  Eigen::Matrix<double, 3, N> u = R.transpose() * set.gather(x, e) - set.gather(set.rest(), e);
  const Eigen::Matrix<double, 3 * N, 1> ku =
      set.stiffness(e) * Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>>(u.data());
  const Eigen::Matrix<double, 3, N> fe = R * Eigen::Map<const Eigen::Matrix<double, 3, N>>(ku.data());
  for (int a = 0; a < N; ++a) f.col(set.cells()(e, a)) -= fe.col(a);
  }
}

template <class E>
void CorotationalFEM<E>::add_element_stiffness(Index e, double scale, BlockSparseMatrix& A) const {
  if constexpr (kTetKernel) {
    add_tet_stiffness(this->elements_, rotations_[e], lambda_, mu_, e, scale, A);
    return;
  } else {
  constexpr int N = E::num_nodes;
  const auto& set = this->elements_;
  const Mat3 sR = scale * rotations_[e];
  const Mat3& R = rotations_[e];
  const auto& K = set.stiffness(e);
  const int* ids = set.block_ids(e);
  // K_e is symmetric: rotate the upper blocks and mirror them.
  for (int a = 0; a < N; ++a)
    for (int b = a; b < N; ++b) {
      const Mat3 block = sR * K.template block<3, 3>(3 * a, 3 * b) * R.transpose();
      A.block(ids[a * N + b]) += block;
      if (b != a) A.block(ids[b * N + a]) += block.transpose();
    }
  }
}

template <class E>
void CorotationalFEM<E>::add_forces(const Nodes& x, Nodes& f) const {
  for (Index e = 0; e < this->elements_.num_elements(); ++e) add_element_forces(e, x, f);
}

template <class E>
void CorotationalFEM<E>::add_stiffness(double scale, BlockSparseMatrix& A) const {
  for (Index e = 0; e < this->elements_.num_elements(); ++e) add_element_stiffness(e, scale, A);
}

template <class E>
void CorotationalFEM<E>::add_linearized_forces_and_stiffness(const Nodes& y, Nodes& f, double scale,
                                                             BlockSparseMatrix& A) const {
  // One sweep: each element's data is read from memory once for both.
  for (Index e = 0; e < this->elements_.num_elements(); ++e) {
    add_element_forces(e, y, f);
    add_element_stiffness(e, scale, A);
  }
}

template <class E>
double CorotationalFEM<E>::energy(const Nodes& x) const {
  constexpr int N = E::num_nodes;
  const auto& set = this->elements_;
  double total = 0;
  for (Index e = 0; e < set.num_elements(); ++e) {
    if constexpr (kTetKernel) {
      const Mat3 strain = tet_strain(set, rotations_[e], e, x);
      total += 0.5 * set.element(e).volume * (strain.cwiseProduct(linear_stress(strain, lambda_, mu_))).sum();
    } else {
      Eigen::Matrix<double, 3, N> u = rotations_[e].transpose() * set.gather(x, e) - set.gather(set.rest(), e);
      const Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>> uv(u.data());
      total += 0.5 * uv.dot(set.stiffness(e) * uv);
    }
  }
  return total;
}

template <class E>
void CorotationalFEM<E>::add_tangent_stiffness(const Nodes& x, double scale, BlockSparseMatrix& A) const {
  for (Index e = 0; e < this->elements_.num_elements(); ++e) {
    if constexpr (kTetKernel)
      if (add_tet_tangent(this->elements_, rotations_[e], lambda_, mu_, e, x, scale, A)) continue;
    add_element_stiffness(e, scale, A);
  }
}

template class CorotationalFEM<Tet4>;
template class CorotationalFEM<Hex8>;
template class CorotationalFEM<Hex20>;

}  // namespace corotate
