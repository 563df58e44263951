// What explicit integration asks of a model beyond ForceModel::evaluate: its own velocity
// damping (spring dashpots, eq. 2) and bounds of K and C valid in every configuration, for a
// stable step that never needs re-estimating. Found through ForceModel::explicit_traits();
// models without either (the finite-element models) return nullptr there and explicit steps
// use evaluate() and the linearised system at the current positions.
#pragma once

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class ExplicitTraits {
 public:
  virtual ~ExplicitTraits() = default;
  virtual bool has_damping() const = 0;
  // f += elastic forces at x plus the model's damping forces at velocities v, in one sweep
  // (the per-substep kernel of explicit steps).
  virtual void add_forces_and_damping(const Nodes& x, const Nodes& v, Nodes& f) const = 0;
  // A += scale * C(x), C = -d f_damping / dv.
  virtual void add_damping_matrix(const Nodes& x, double scale, BlockSparseMatrix& A) const = 0;
  // A += scale * an upper bound of K (resp. C) valid in every configuration.
  virtual void add_stiffness_bound(double scale, BlockSparseMatrix& A) const = 0;
  virtual void add_damping_bound(double scale, BlockSparseMatrix& A) const = 0;
};

}  // namespace corotate
