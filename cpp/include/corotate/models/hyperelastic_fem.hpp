// Total-Lagrangian hyperelastic FEM on solid elements (Tet4, Hex8, Hex20) with a
// constitutive law Law (StVK, StableNeoHookean, FixedCorotated; see corotate/materials/).
//
// Energy  E(x) = sum_e sum_q w_q W(F_q),   F_q = x_e G_q,  G_q = dN/dX at point q,
// forces  f = -dE/dx,  stiffness  K = d2E/dx2 (exact tangent, symmetric).
// w_q = Gauss weight x det J at q; G_q and w_q are computed once from the rest shape with
// the element's stiffness rule (Tet4: one point, F = Ds Dm^-1; Hex8: 2x2x2; Hex20: 3x3x3),
// so at the rest state K equals the linear FEM stiffness exactly.
//
// State: update(x) stores x; add_stiffness and add_linearized_forces use it. The element
// stiffness is recomputed on each call rather than cached: a cache would cost 3N x 3N per
// element (28.8 kB per Hex20) and an explicit integrator never needs it.
// With project_psd each element stiffness is projected to the nearest PSD matrix (see
// psd_projection.hpp) in add_stiffness and add_linearized_forces alike, so the linearised
// force stays f(x) - K (y - x) with the K that is assembled.
#pragma once

#include <vector>

#include "corotate/models/fe_model.hpp"
#include "corotate/models/geometric_stiffness.hpp"

namespace corotate {

template <class E, class Law>
class HyperelasticFEM final : public FEModel<E>, public GeometricStiffness {
 public:
  static constexpr int N = E::num_nodes;
  using NodeMatrix = Eigen::Matrix<double, 3, N>;
  using Gradient = Eigen::Matrix<double, N, 3>;
  using Stiffness = Eigen::Matrix<double, 3 * N, 3 * N>;

  HyperelasticFEM(const Nodes& rest, const Connectivity& cells, const Material& material, bool project_psd = false);

  const char* name() const override { return Law::name; }
  bool is_linear() const override { return false; }
  void update(const Nodes& x) override { state_ = x; }
  void add_forces(const Nodes& x, Nodes& f) const override;
  void add_stiffness(double scale, BlockSparseMatrix& A) const override;
  void add_linearized_forces(const Nodes& y, Nodes& f) const override;
  void add_linearized_forces_and_stiffness(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix& A) const override;
  double energy(const Nodes& x) const override;

  // K_sigma at x; S = F^-1 P for laws other than StVK, which needs det F > 0 at every
  // quadrature point (InvalidInput naming the element otherwise).
  void add_geometric_stiffness(const Nodes& x, double scale, BlockSparseMatrix& A) const override;

  const Law& law() const { return law_; }
  bool projects_psd() const { return project_psd_; }

 private:
  struct Point {
    Gradient G;  // dN/dX at the point
    double w;    // weight x det J
  };
  const Point& point(Index e, int q) const { return points_[e * num_points_ + q]; }
  void element_forces(Index e, const NodeMatrix& xe, NodeMatrix& fe) const;
  void element_stiffness(Index e, const NodeMatrix& xe, Stiffness& Ke) const;
  void scatter(Index e, const NodeMatrix& fe, Nodes& f) const;
  void scatter(Index e, double scale, const Stiffness& Ke, BlockSparseMatrix& A) const;

  Law law_;
  bool project_psd_;
  int num_points_;
  std::vector<Point> points_;  // num_elements x num_points_
  Nodes state_;                // positions of the last update
};

}  // namespace corotate
