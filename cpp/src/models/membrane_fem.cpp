#include "corotate/models/membrane_fem.hpp"

#include <cmath>

#include "corotate/fem/element_set.hpp"  // validate_mesh
#include "corotate/materials/psd_projection.hpp"
#include "corotate/models/hyperelastic_kernels.hpp"

namespace corotate {

namespace {
double plane_stress_lambda(const Material& m) {
  const double lambda = m.lame_lambda(), mu = m.lame_mu();
  return 2 * lambda * mu / (lambda + 2 * mu);
}
}  // namespace

MembraneFEM::MembraneFEM(const Nodes& rest, const Connectivity& cells, const Material& material, double thickness,
                         bool project_psd)
    : rest_(rest), cells_(cells), thickness_(thickness), density_(material.density), project_psd_(project_psd), state_(rest) {
  validate_mesh(rest, cells, N, Tri3::name);
  material.validate();
  if (!std::isfinite(thickness) || thickness <= 0)
    throw InvalidInput("thickness of the triangle sheet must be positive and finite, got " + std::to_string(thickness));
  law_ = StVK{plane_stress_lambda(material), material.lame_mu()};
  pattern_ = BlockSparseMatrix::from_cells(rest.cols(), cells);
  elements_.reserve(cells.rows());
  block_ids_.resize(cells.rows() * N * N);
  for (Index e = 0; e < cells.rows(); ++e) {
    const Tri3::Rest r = Tri3::rest(gather(rest, e), e);
    elements_.push_back({r.G, thickness * r.area});
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) block_ids_[(e * N + a) * N + b] = pattern_.block_index(cells(e, a), cells(e, b));
  }
}

MembraneFEM::NodeMatrix MembraneFEM::gather(const Nodes& x, Index e) const {
  NodeMatrix xe;
  for (int a = 0; a < N; ++a) xe.col(a) = x.col(cells_(e, a));
  return xe;
}

BlockSparseMatrix MembraneFEM::mass_matrix(bool lumped) const {
  BlockSparseMatrix M = pattern_;
  M.set_zero();
  for (Index e = 0; e < static_cast<Index>(elements_.size()); ++e) {
    const double m = density_ * elements_[e].w;  // rho t A
    const Eigen::Matrix3d me = Tri3::consistent_mass(m);
    const Vec3 ml = Tri3::lumped_mass(m);
    const int* ids = block_ids_.data() + e * N * N;
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) {
        if (lumped && a != b) continue;
        M.block(ids[a * N + b]).diagonal().array() += lumped ? ml(a) : me(a, b);
      }
  }
  return M;
}

void MembraneFEM::element_forces(Index e, const NodeMatrix& xe, NodeMatrix& fe) const {
  const Element& el = elements_[e];
  fe.setZero();
  const Eigen::Matrix<double, 3, 2> F = deformation_gradient<N, 2>(xe, el.G);
  add_point_forces<StVK, N, 2>(law_, F, el.G, el.w, fe);
}

void MembraneFEM::element_stiffness(Index e, const NodeMatrix& xe, Stiffness& Ke) const {
  const Element& el = elements_[e];
  Ke.setZero();
  const Eigen::Matrix<double, 3, 2> F = deformation_gradient<N, 2>(xe, el.G);
  add_point_stiffness<StVK, N, 2>(law_, F, el.G, el.w, Ke);
  // Ke is symmetric up to rounding; the eigen solver reads its lower triangle.
  if (project_psd_) project_psd<3 * N>(Ke);
}

void MembraneFEM::scatter(Index e, const NodeMatrix& fe, Nodes& f) const {
  for (int a = 0; a < N; ++a) f.col(cells_(e, a)) += fe.col(a);
}

void MembraneFEM::scatter(Index e, double scale, const Stiffness& Ke, BlockSparseMatrix& A) const {
  const int* ids = block_ids_.data() + e * N * N;
  for (int a = 0; a < N; ++a)
    for (int b = a; b < N; ++b) {
      Mat3 block = scale * Ke.block<3, 3>(3 * a, 3 * b);
      if (b == a) block = 0.5 * (block + block.transpose()).eval();
      A.block(ids[a * N + b]) += block;
      if (b != a) A.block(ids[b * N + a]) += block.transpose();
    }
}

void MembraneFEM::add_forces(const Nodes& x, Nodes& f) const {
  NodeMatrix fe;
  for (Index e = 0; e < static_cast<Index>(elements_.size()); ++e) {
    element_forces(e, gather(x, e), fe);
    scatter(e, fe, f);
  }
}

void MembraneFEM::add_stiffness(double scale, BlockSparseMatrix& A) const {
  Stiffness Ke;
  for (Index e = 0; e < static_cast<Index>(elements_.size()); ++e) {
    element_stiffness(e, gather(state_, e), Ke);
    scatter(e, scale, Ke, A);
  }
}

void MembraneFEM::add_linearized_forces(const Nodes& y, Nodes& f) const {
  Stiffness Ke;
  NodeMatrix fe;
  for (Index e = 0; e < static_cast<Index>(elements_.size()); ++e) {
    const NodeMatrix xe = gather(state_, e);
    const NodeMatrix dy = gather(y, e) - xe;
    element_forces(e, xe, fe);
    element_stiffness(e, xe, Ke);
    Eigen::Map<Eigen::Matrix<double, 9, 1>>(fe.data()) -= Ke * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dy.data());
    scatter(e, fe, f);
  }
}

void MembraneFEM::add_linearized_forces_and_stiffness(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix& A) const {
  Stiffness Ke;
  NodeMatrix fe;
  for (Index e = 0; e < static_cast<Index>(elements_.size()); ++e) {
    const NodeMatrix xe = gather(state_, e);
    const NodeMatrix dy = gather(y, e) - xe;
    element_forces(e, xe, fe);
    element_stiffness(e, xe, Ke);
    Eigen::Map<Eigen::Matrix<double, 9, 1>>(fe.data()) -= Ke * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dy.data());
    scatter(e, fe, f);
    scatter(e, scale, Ke, A);
  }
}

double MembraneFEM::energy(const Nodes& x) const {
  double total = 0;
  for (Index e = 0; e < static_cast<Index>(elements_.size()); ++e) {
    const Element& el = elements_[e];
    total += el.w * law_.energy(Eigen::Matrix<double, 3, 2>(deformation_gradient<N, 2>(gather(x, e), el.G)));
  }
  return total;
}

void MembraneFEM::add_geometric_stiffness(const Nodes& x, double scale, BlockSparseMatrix& A) const {
  for (Index e = 0; e < static_cast<Index>(elements_.size()); ++e) {
    const Element& el = elements_[e];
    const Eigen::Matrix<double, 3, 2> F = deformation_gradient<N, 2>(gather(x, e), el.G);
    const Eigen::Matrix3d k = point_geometric_stiffness<N, 2>(law_.second_piola(F), el.G, el.w);
    const int* ids = block_ids_.data() + e * N * N;
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) A.block(ids[a * N + b]).diagonal().array() += scale * k(a, b);
  }
}

}  // namespace corotate
