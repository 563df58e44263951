// St. Venant-Kirchhoff membrane on linear triangles (Tri3): cloth-like sheets in 3D and, with
// all nodes in the z = 0 plane, 2D plane-stress bodies.
//
// Per element, F = x_e G is 3 x 2 (see elements/tri3.hpp), E = (F^T F - I)/2 is the 2 x 2
// in-plane Green strain and
//     W = mu E:E + lambda_ps/2 tr(E)^2,   P = F (2 mu E + lambda_ps tr(E) I),
//     energy = t A W,   [f1 f2] from f_a = -t A P G_a^T  (the explainer's -A P Dm^-T),
// with thickness t, rest area A and the plane-stress Lame parameter
//     lambda_ps = 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2),
// because a thin sheet carries no stress through its thickness (sigma_zz = 0 eliminates the
// normal strain). At rest K is the linear plane-stress stiffness t A B^T D B.
// A flat membrane has no stiffness against motion out of its plane (no bending): static
// solves of a flat sheet need out-of-plane loads to be carried by tension or the out-of-plane
// DOFs fixed; dynamics is fine (mass).
//
// update / add_stiffness / add_linearized_forces / project_psd: as HyperelasticFEM.
#pragma once

#include <vector>

#include "corotate/elements/tri3.hpp"
#include "corotate/material.hpp"
#include "corotate/materials/stvk.hpp"
#include "corotate/models/force_model.hpp"
#include "corotate/models/geometric_stiffness.hpp"

namespace corotate {

class MembraneFEM final : public ForceModel, public GeometricStiffness {
 public:
  static constexpr int N = 3;
  using NodeMatrix = Eigen::Matrix<double, 3, N>;
  using Stiffness = Eigen::Matrix<double, 3 * N, 3 * N>;

  // rest: 3 x n; cells: m x 3; thickness > 0 [m].
  MembraneFEM(const Nodes& rest, const Connectivity& cells, const Material& material, double thickness,
              bool project_psd = false);

  const char* name() const override { return StVK::name; }
  Index num_nodes() const override { return rest_.cols(); }
  const Nodes& rest_positions() const override { return rest_; }
  const BlockSparseMatrix& pattern() const override { return pattern_; }
  BlockSparseMatrix mass_matrix(bool lumped) const override;
  bool is_linear() const override { return false; }
  void update(const Nodes& x) override { state_ = x; }
  void add_forces(const Nodes& x, Nodes& f) const override;
  void add_stiffness(double scale, BlockSparseMatrix& A) const override;
  void add_linearized_forces(const Nodes& y, Nodes& f) const override;
  void add_linearized_forces_and_stiffness(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix& A) const override;
  double energy(const Nodes& x) const override;
  void add_geometric_stiffness(const Nodes& x, double scale, BlockSparseMatrix& A) const override;

  double thickness() const { return thickness_; }
  const StVK& law() const { return law_; }

 private:
  struct Element {
    Tri3::Gradient G;
    double w;  // thickness x rest area
  };
  NodeMatrix gather(const Nodes& x, Index e) const;
  void element_forces(Index e, const NodeMatrix& xe, NodeMatrix& fe) const;
  void element_stiffness(Index e, const NodeMatrix& xe, Stiffness& Ke) const;
  void scatter(Index e, const NodeMatrix& fe, Nodes& f) const;
  void scatter(Index e, double scale, const Stiffness& Ke, BlockSparseMatrix& A) const;

  Nodes rest_;
  Connectivity cells_;
  double thickness_, density_;
  StVK law_;
  bool project_psd_;
  std::vector<Element> elements_;
  BlockSparseMatrix pattern_;
  std::vector<int> block_ids_;  // 9 per element
  Nodes state_;
};

}  // namespace corotate
