// Co-rotational linear FEM (paper section 2.2, eqs 3-4).
//
// Per element the rotation R_e is the polar rotation of the deformation gradient at the
// element centre (tet: F = Ds Dm^-1), extracted by rotation_extraction.hpp warm-started from
// the previous call's rotation. Forces are the linear element forces computed in the
// element's unrotated frame and rotated back,
//     f_e = -R_e K_e (R_e^T x_e - X_e),                              (eq. 3)
// the stiffness is R_e K_e R_e^T (eq. 4) and the energy 1/2 u^T K_e u, u = R_e^T x_e - X_e.
// With R_e held fixed the force is linear in x, so the force linearised about x and
// evaluated at y is eq. (3) at y with the rotations of x.
// This general kernel keeps K_e (1.1 kB per tet, 28.8 kB per Hex20); linear tets have their
// own kernel without K_e (corotational_tet_kernel.hpp). Both have the exact tangent.
//
// Exact tangent of the general (hex) element, K_T = -df/dx with dR/dx included.
// Notation: G (N x 3) the shape gradients dN/dX at the centre, g_b its row b, F = x G,
// R = polar(F), S = R^T F (symmetric), y_b = R^T x_b, u_b = y_b - X_b, k = K_e u (3-vectors
// k_a per node), so f_a = -R k_a.
//  * Rotation rate. dR = R [theta]x; R^T F stays symmetric, so skew(R^T dF - [theta]x S) = 0,
//    which is (tr(S) I - S) theta = vee(W - W^T), W = R^T dF = sum_b (R^T dx_b) g_b^T. With
//    vee(w g^T - g w^T) = g x w:
//        theta = sum_b A_b dx_b,   A_b = H^-1 [g_b]x R^T,   H = tr(S) I - S.
//  * Unrotated displacement. du_b = dR^T x_b + R^T dx_b = y_b x theta + R^T dx_b.
//  * Force. -df_a = dR k_a + R dk_a = R (theta x k_a) + R sum_b K_ab du_b, so
//        K_T(a, b) = R K_ab R^T + R C_a A_b,   C_a = sum_c K_ac [y_c]x - [k_a]x.
//    K_e annihilates rigid rotations of the rest shape (sum_c K_ac [X_c]x = 0), so the first
//    sum is computed as sum_c K_ac [u_c]x: C_a = O(u), and K_T = R K_e R^T at rest or under
//    a rigid motion. The correction is rank 3 per element (C A, 3N x 3 times 3 x 3N).
// K_T is not symmetric: the force -R K_e u is not the gradient of an energy when R is the
// polar rotation at one point of a multi-point element (the gradient of 1/2 u^T K_e u would
// add -A^T sum_c [y_c]x^T k_c, the moment of the unrotated forces about the unrotated nodes,
// which vanishes for a tet by the symmetry of its stress but not for a hex). So the kernel
// declares symmetric_tangent = false: the assembled model then scatters all N x N blocks
// as they are, ForceModel::symmetric_tangent() reports it, and the static solver solves with
// a non-symmetric sparse LU (see static_solver.hpp). The Model stiffness R K_e R^T and the
// forces (the dynamics path) are unchanged. Where H is near singular (inverted elements)
// tangent() returns false and the element uses R K_e R^T.
#pragma once

#include "corotate/elements/element_matrices.hpp"
#include "corotate/fem/element_kernel.hpp"
#include "corotate/materials/determinant_derivatives.hpp"  // cross_matrix
#include "corotate/models/rotation_extraction.hpp"

namespace corotate {

template <class E>
class CorotationalKernel {
 public:
  static constexpr int N = E::num_nodes;
  using ElementType = E;
  using NodeMatrix = typename KernelTypes<E>::NodeMatrix;
  using Stiffness = typename KernelTypes<E>::Stiffness;
  using DofVector = Eigen::Matrix<double, 3 * N, 1>;
  static constexpr const char* name = "corotational";
  static constexpr bool constant_stiffness = false;
  static constexpr bool forces_linear_given_frame = true;
  static constexpr bool has_geometric_stiffness = false;
  static constexpr bool symmetric_tangent = false;  // see the derivation above
  struct Element {
    Stiffness K;                       // K_e at rest
    NodeMatrix X;                      // rest positions
    Eigen::Matrix<double, N, 3> G;     // dN/dX at the centre
  };
  struct Frame {
    Mat3 R;
  };
  struct Cache {
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // warm start of the extraction
  };

  CorotationalKernel(const RegionMaterials& materials, const ModelOptions&) : materials_(materials.materials) {}

  Element precompute(const NodeMatrix& X, Index e, int region) const {
    return {linear_stiffness<E>(quadrature_points<E>(X, e, 1.0), materials_[region]), X, centre_gradient<E>(X, e)};
  }
  double volume_ratio(const Element& el, const Frame&, const NodeMatrix& x) const {
    return Mat3(x * el.G).determinant();
  }
  Frame frame(const Element& el, const NodeMatrix& x, Cache& cache) const {
    return {extract_rotation(Mat3(x * el.G), cache.q)};
  }
  double energy(const Element& el, const Frame& fr, const NodeMatrix& x) const {
    const NodeMatrix u = fr.R.transpose() * x - el.X;
    const Eigen::Map<const DofVector> uv(u.data());
    return 0.5 * uv.dot(el.K * uv);
  }
  void forces(const Element& el, const Frame& fr, const NodeMatrix& x, NodeMatrix& f) const {
    const NodeMatrix u = fr.R.transpose() * x - el.X;
    const DofVector ku = el.K * Eigen::Map<const DofVector>(u.data());
    f.noalias() = -fr.R * Eigen::Map<const NodeMatrix>(ku.data());
  }
  template <class Sink>
  void stiffness(const Element& el, const Frame& fr, const NodeMatrix&, Sink& K) const {
    for (int a = 0; a < N; ++a)
      for (int b = a; b < N; ++b) K.add(a, b, fr.R * el.K.template block<3, 3>(3 * a, 3 * b) * fr.R.transpose());
  }
  // Exact tangent, all N x N blocks (not symmetric); derivation at the top of this file.
  bool tangent(const Element& el, const Frame& fr, const NodeMatrix& x, Stiffness& K) const {
    const Mat3& R = fr.R;
    Mat3 S, H_inv;
    if (!polar_rotation_derivative(R, Mat3(x * el.G), S, H_inv)) return false;
    const NodeMatrix u = R.transpose() * x - el.X;
    const DofVector ku = el.K * Eigen::Map<const DofVector>(u.data());
    Eigen::Matrix<double, 3, 3 * N> A;   // the A_b side by side
    Eigen::Matrix<double, 3 * N, 3> RC;  // the R C_a stacked
    for (int b = 0; b < N; ++b)
      A.template block<3, 3>(0, 3 * b) = H_inv * cross_matrix(el.G.row(b).transpose()) * R.transpose();
    for (int a = 0; a < N; ++a) {
      Mat3 C = -cross_matrix(ku.template segment<3>(3 * a));
      for (int c = 0; c < N; ++c) C.noalias() += el.K.template block<3, 3>(3 * a, 3 * c) * cross_matrix(u.col(c));
      RC.template block<3, 3>(3 * a, 0) = R * C;
    }
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b)
        K.template block<3, 3>(3 * a, 3 * b).noalias() =
            R * el.K.template block<3, 3>(3 * a, 3 * b) * R.transpose() +
            RC.template block<3, 3>(3 * a, 0) * A.template block<3, 3>(0, 3 * b);
    return true;
  }

 private:
  std::vector<Material> materials_;  // by region
};

}  // namespace corotate

#include "corotate/models/corotational_tet_kernel.hpp"
