#include "corotate/models/corotational_fem.hpp"

#include "corotate/models/rotation_extraction.hpp"

namespace corotate {

template <class E>
CorotationalFEM<E>::CorotationalFEM(const Nodes& rest, const Connectivity& cells, const Material& material)
    : FEModel<E>(rest, cells, material),
      rotations_(cells.rows(), Mat3::Identity()),
      warm_start_(cells.rows(), Eigen::Quaterniond::Identity()) {}

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
  constexpr int N = E::num_nodes;
  const auto& set = this->elements_;
  const Mat3& R = rotations_[e];
  // Unrotated displacement u = R^T x_e - X_e, element force in that frame -K u, rotated back.
  Eigen::Matrix<double, 3, N> u = R.transpose() * set.gather(x, e) - set.gather(set.rest(), e);
  const Eigen::Matrix<double, 3 * N, 1> ku =
      set.element(e).stiffness * Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>>(u.data());
  const Eigen::Matrix<double, 3, N> fe = R * Eigen::Map<const Eigen::Matrix<double, 3, N>>(ku.data());
  for (int a = 0; a < N; ++a) f.col(set.cells()(e, a)) -= fe.col(a);
}

template <class E>
void CorotationalFEM<E>::add_element_stiffness(Index e, double scale, BlockSparseMatrix& A) const {
  constexpr int N = E::num_nodes;
  const auto& set = this->elements_;
  const Mat3 sR = scale * rotations_[e];
  const Mat3& R = rotations_[e];
  const auto& K = set.element(e).stiffness;
  const int* ids = set.block_ids(e);
  // K_e is symmetric: rotate the upper blocks and mirror them.
  for (int a = 0; a < N; ++a)
    for (int b = a; b < N; ++b) {
      const Mat3 block = sR * K.template block<3, 3>(3 * a, 3 * b) * R.transpose();
      A.block(ids[a * N + b]) += block;
      if (b != a) A.block(ids[b * N + a]) += block.transpose();
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
void CorotationalFEM<E>::add_forces_and_stiffness(const Nodes& x, Nodes& f, double scale,
                                                  BlockSparseMatrix& A) const {
  // One sweep: each element's K_e is read from memory once for both.
  for (Index e = 0; e < this->elements_.num_elements(); ++e) {
    add_element_forces(e, x, f);
    add_element_stiffness(e, scale, A);
  }
}

template <class E>
double CorotationalFEM<E>::energy(const Nodes& x) const {
  constexpr int N = E::num_nodes;
  const auto& set = this->elements_;
  double total = 0;
  for (Index e = 0; e < set.num_elements(); ++e) {
    Eigen::Matrix<double, 3, N> u = rotations_[e].transpose() * set.gather(x, e) - set.gather(set.rest(), e);
    const Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>> uv(u.data());
    total += 0.5 * uv.dot(set.element(e).stiffness * uv);
  }
  return total;
}

template class CorotationalFEM<Tet4>;
template class CorotationalFEM<Hex8>;
template class CorotationalFEM<Hex20>;

}  // namespace corotate
