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
// own kernel without K_e and with the exact tangent (corotational_tet_kernel.hpp). Here the
// tangent is R K_e R^T, which leaves out dR/dx.
#pragma once

#include "corotate/elements/element_matrices.hpp"
#include "corotate/fem/element_kernel.hpp"
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

  CorotationalKernel(const Material& material, const ModelOptions&) : material_(material) {}

  Element precompute(const NodeMatrix& X, Index e) const {
    return {linear_stiffness<E>(quadrature_points<E>(X, e, 1.0), material_), X, centre_gradient<E>(X, e)};
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
  bool tangent(const Element&, const Frame&, const NodeMatrix&, Stiffness&) const { return false; }

 private:
  Material material_;
};

}  // namespace corotate

#include "corotate/models/corotational_tet_kernel.hpp"
