// Linear FEM: f = -K (x - X) with the rest stiffness K assembled once.
// Exact for small displacements; grows artificially under large rotations (paper 2.2.2).
#pragma once

#include "corotate/models/fe_model.hpp"

namespace corotate {

template <class E>
class LinearFEM final : public FEModel<E> {
 public:
  LinearFEM(const Nodes& rest, const Connectivity& cells, const Material& material);

  const char* name() const override { return "linear"; }
  bool is_linear() const override { return true; }
  void update(const Nodes&) override {}
  void add_forces(const Nodes& x, Nodes& f) const override;
  void add_linearized_forces(const Nodes& y, Nodes& f) const override { add_forces(y, f); }
  void add_stiffness(double scale, BlockSparseMatrix& A) const override;
  double energy(const Nodes& x) const override;

 private:
  BlockSparseMatrix stiffness_;   // global K at rest
  mutable Vec displacement_, kd_;  // work buffers, sized once
};

}  // namespace corotate
