// Linear FEM: f = -K (x - X) with the rest stiffness K = sum_e K_e, K_e = integral of
// B^T H B dV (elements/element_matrices.hpp). Exact for small displacements; grows
// artificially under large rotations (paper 2.2.2). The kernel only supplies K_e: its
// stiffness never changes, so the assembled model builds K once and frees K_e.
#pragma once

#include "corotate/elements/element_matrices.hpp"
#include "corotate/fem/element_kernel.hpp"

namespace corotate {

template <class E>
class LinearKernel {
 public:
  using ElementType = E;
  using NodeMatrix = typename KernelTypes<E>::NodeMatrix;
  using Stiffness = typename KernelTypes<E>::Stiffness;
  static constexpr const char* name = "linear";
  static constexpr bool constant_stiffness = true;
  static constexpr bool forces_linear_given_frame = true;
  static constexpr bool has_geometric_stiffness = false;
  struct Element {
    Stiffness K;
  };
  using Frame = NoFrame;
  using Cache = NoCache;

  LinearKernel(const RegionMaterials& materials, const ModelOptions&) : materials_(materials.materials) {}
  Element precompute(const NodeMatrix& X, Index e, int region) const {
    return {linear_stiffness<E>(quadrature_points<E>(X, e, 1.0), materials_[region])};
  }
  template <class Sink>
  void stiffness(const Element& el, const Frame&, const NodeMatrix&, Sink& K) const {
    for (int a = 0; a < E::num_nodes; ++a)
      for (int b = a; b < E::num_nodes; ++b) K.add(a, b, el.K.template block<3, 3>(3 * a, 3 * b));
  }

 private:
  std::vector<Material> materials_;  // by region
};

}  // namespace corotate
