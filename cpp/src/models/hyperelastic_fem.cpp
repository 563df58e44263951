#include "corotate/models/hyperelastic_fem.hpp"

#include <sstream>

#include "corotate/materials/fixed_corotated.hpp"
#include "corotate/materials/psd_projection.hpp"
#include "corotate/materials/stable_neo_hookean.hpp"
#include "corotate/materials/stvk.hpp"
#include "corotate/models/hyperelastic_kernels.hpp"

namespace corotate {

template <class E, class Law>
HyperelasticFEM<E, Law>::HyperelasticFEM(const Nodes& rest, const Connectivity& cells, const Material& material,
                                         bool project_psd)
    : FEModel<E>(rest, cells, material),  // validates mesh, material, rejects inverted elements
      law_{material.lame_lambda(), material.lame_mu()},
      project_psd_(project_psd),
      num_points_(static_cast<int>(E::stiffness_rule().points.size())),
      state_(rest) {
  auto& set = this->elements_;
  set.release_stiffness();  // the linear K_e is not used here
  const auto& rule = E::stiffness_rule();
  points_.reserve(set.num_elements() * num_points_);
  for (Index e = 0; e < set.num_elements(); ++e) {
    const NodeMatrix X = set.gather(rest, e);
    for (int q = 0; q < num_points_; ++q) {
      const Mat3 J = checked_jacobian<E>(X, rule.points[q], e);
      points_.push_back({E::shape_gradient(rule.points[q]) * J.inverse(), rule.weights[q] * J.determinant()});
    }
  }
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::element_forces(Index e, const NodeMatrix& xe, NodeMatrix& fe) const {
  fe.setZero();
  for (int q = 0; q < num_points_; ++q) {
    const Point& p = point(e, q);
    const Mat3 F = deformation_gradient<N, 3>(xe, p.G);
    add_point_forces<Law, N, 3>(law_, F, p.G, p.w, fe);
  }
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::element_stiffness(Index e, const NodeMatrix& xe, Stiffness& Ke) const {
  Ke.setZero();
  for (int q = 0; q < num_points_; ++q) {
    const Point& p = point(e, q);
    const Mat3 F = deformation_gradient<N, 3>(xe, p.G);
    add_point_stiffness<Law, N, 3>(law_, F, p.G, p.w, Ke);
  }
  // Ke is symmetric up to rounding; the eigen solver reads its lower triangle.
  if (project_psd_) project_psd<3 * N>(Ke);
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::scatter(Index e, const NodeMatrix& fe, Nodes& f) const {
  for (int a = 0; a < N; ++a) f.col(this->elements_.cells()(e, a)) += fe.col(a);
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::scatter(Index e, double scale, const Stiffness& Ke, BlockSparseMatrix& A) const {
  const int* ids = this->elements_.block_ids(e);
  // Upper blocks mirrored, diagonal blocks symmetrised: the assembled matrix is exactly symmetric.
  for (int a = 0; a < N; ++a)
    for (int b = a; b < N; ++b) {
      Mat3 block = scale * Ke.template block<3, 3>(3 * a, 3 * b);
      if (b == a) block = 0.5 * (block + block.transpose()).eval();
      A.block(ids[a * N + b]) += block;
      if (b != a) A.block(ids[b * N + a]) += block.transpose();
    }
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::add_forces(const Nodes& x, Nodes& f) const {
  NodeMatrix fe;
  for (Index e = 0; e < this->elements_.num_elements(); ++e) {
    element_forces(e, this->elements_.gather(x, e), fe);
    scatter(e, fe, f);
  }
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::add_stiffness(double scale, BlockSparseMatrix& A) const {
  Stiffness Ke;
  for (Index e = 0; e < this->elements_.num_elements(); ++e) {
    element_stiffness(e, this->elements_.gather(state_, e), Ke);
    scatter(e, scale, Ke, A);
  }
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::add_linearized_forces(const Nodes& y, Nodes& f) const {
  const auto& set = this->elements_;
  Stiffness Ke;
  NodeMatrix fe;
  for (Index e = 0; e < set.num_elements(); ++e) {
    const NodeMatrix xe = set.gather(state_, e);
    const NodeMatrix dy = set.gather(y, e) - xe;
    element_forces(e, xe, fe);
    element_stiffness(e, xe, Ke);
    Eigen::Map<Eigen::Matrix<double, 3 * N, 1>>(fe.data()) -= Ke * Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>>(dy.data());
    scatter(e, fe, f);
  }
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::add_linearized_forces_and_stiffness(const Nodes& y, Nodes& f, double scale,
                                                                  BlockSparseMatrix& A) const {
  // One sweep: each element's tangent is evaluated once for both.
  const auto& set = this->elements_;
  Stiffness Ke;
  NodeMatrix fe;
  for (Index e = 0; e < set.num_elements(); ++e) {
    const NodeMatrix xe = set.gather(state_, e);
    const NodeMatrix dy = set.gather(y, e) - xe;
    element_forces(e, xe, fe);
    element_stiffness(e, xe, Ke);
    Eigen::Map<Eigen::Matrix<double, 3 * N, 1>>(fe.data()) -= Ke * Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>>(dy.data());
    scatter(e, fe, f);
    scatter(e, scale, Ke, A);
  }
}

template <class E, class Law>
double HyperelasticFEM<E, Law>::energy(const Nodes& x) const {
  double total = 0;
  for (Index e = 0; e < this->elements_.num_elements(); ++e) {
    const NodeMatrix xe = this->elements_.gather(x, e);
    for (int q = 0; q < num_points_; ++q) {
      const Point& p = point(e, q);
      total += p.w * law_.energy(Mat3(deformation_gradient<N, 3>(xe, p.G)));
    }
  }
  return total;
}

template <class E, class Law>
void HyperelasticFEM<E, Law>::add_geometric_stiffness(const Nodes& x, double scale, BlockSparseMatrix& A) const {
  const auto& set = this->elements_;
  for (Index e = 0; e < set.num_elements(); ++e) {
    const NodeMatrix xe = set.gather(x, e);
    Eigen::Matrix<double, N, N> k = Eigen::Matrix<double, N, N>::Zero();
    for (int q = 0; q < num_points_; ++q) {
      const Point& p = point(e, q);
      const Mat3 F = deformation_gradient<N, 3>(xe, p.G);
      Mat3 S;
      if constexpr (std::is_same_v<Law, StVK>) {
        S = law_.second_piola(F);
      } else {
        const double J = F.determinant();
        if (!(J > 0)) {
          std::ostringstream msg;
          msg << "element " << e << " (" << E::name << ") is inverted or flat at these positions (det F = " << J
              << "), so its second Piola-Kirchhoff stress, and the geometric stiffness, are undefined";
          throw InvalidInput(msg.str());
        }
        S = F.inverse() * law_.stress(F);
        S = 0.5 * (S + S.transpose()).eval();  // symmetric in exact arithmetic
      }
      k += point_geometric_stiffness<N, 3>(S, p.G, p.w);
    }
    const int* ids = set.block_ids(e);
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) A.block(ids[a * N + b]).diagonal().array() += scale * k(a, b);
  }
}

template class HyperelasticFEM<Tet4, StVK>;
template class HyperelasticFEM<Hex8, StVK>;
template class HyperelasticFEM<Hex20, StVK>;
template class HyperelasticFEM<Tet4, StableNeoHookean>;
template class HyperelasticFEM<Hex8, StableNeoHookean>;
template class HyperelasticFEM<Hex20, StableNeoHookean>;
template class HyperelasticFEM<Tet4, FixedCorotated>;
template class HyperelasticFEM<Hex8, FixedCorotated>;
template class HyperelasticFEM<Hex20, FixedCorotated>;

}  // namespace corotate
