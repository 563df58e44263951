// Co-rotational linear FEM (paper section 2.2, eqs 3-4).
//
// Per element the rotation R_e is the polar rotation of the deformation gradient at the
// element centre (tet: F = Ds Dm^-1). Forces are the linear element forces computed in the
// element's unrotated frame and rotated back:
//     f_e = -R_e K_e (R_e^T x_e - X_e),
// and the stiffness is the rotated element stiffness R_e K_e R_e^T (eq. 4), scattered into
// the fixed global pattern.
#pragma once

#include <Eigen/Geometry>
#include <type_traits>
#include <vector>

#include "corotate/models/fe_model.hpp"

namespace corotate {

template <class E>
class CorotationalFEM final : public FEModel<E> {
 public:
  CorotationalFEM(const Nodes& rest, const Connectivity& cells, const Material& material);

  const char* name() const override { return "corotational"; }
  bool is_linear() const override { return false; }
  void update(const Nodes& x) override;
  void add_forces(const Nodes& x, Nodes& f) const override;
  void add_stiffness(double scale, BlockSparseMatrix& A) const override;
  // With the rotations of the last update held fixed, the force formula is linear in x,
  // so the linearised force at y is the same formula evaluated at y.
  void add_linearized_forces(const Nodes& y, Nodes& f) const override { add_forces(y, f); }
  void add_linearized_forces_and_stiffness(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix& A) const override;
  double energy(const Nodes& x) const override;
  // Tets: the exact derivative of eq. (3)'s forces, rotation terms included (consistent
  // tangent of the polar rotation); elements whose rotation derivative is singular (inverted
  // or degenerate) and hexes fall back to R K_e R^T.
  void add_tangent_stiffness(const Nodes& x, double scale, BlockSparseMatrix& A) const override;

  // R_e of the last update (3 x 3 per element).
  const std::vector<Mat3>& rotations() const { return rotations_; }

 private:
  void add_element_forces(Index e, const Nodes& x, Nodes& f) const;
  void add_element_stiffness(Index e, double scale, BlockSparseMatrix& A) const;

  // Linear tets with an isotropic material need no K_e: with a_i = R dN_i/dX the rotated
  // blocks are V (lambda a_i a_j^T + mu a_j a_i^T + mu (a_i . a_j) I), and the force is
  // -V R sigma dN_i/dX with sigma the linear stress of the unrotated strain sym(R^T F) - I.
  // Identical to R K_e R^T and eq. (3), at a fraction of the memory traffic.
  static constexpr bool kTetKernel = std::is_same_v<E, Tet4>;

  double lambda_, mu_;
  std::vector<Mat3> rotations_;
  std::vector<Eigen::Quaterniond> warm_start_;  // previous rotation, to start the iteration from
};

}  // namespace corotate
