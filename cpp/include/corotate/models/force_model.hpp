// The interface every force model provides; integrators and solvers depend on this only.
//
// A step calls update(x) once (per-element state such as rotations), then asks for forces
// and stiffness at that state. Stiffness means K = -df/dx (for the co-rotational model the
// usual approximation R K_e R^T that ignores the derivative of R).
#pragma once

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class ForceModel {
 public:
  virtual ~ForceModel() = default;

  virtual const char* name() const = 0;
  virtual Index num_nodes() const = 0;
  virtual const Nodes& rest_positions() const = 0;
  // Sparsity of the stiffness (and mass) matrices; fixed for the life of the model.
  virtual const BlockSparseMatrix& pattern() const = 0;
  // Mass matrix in pattern(): consistent, or lumped (diagonal blocks only).
  virtual BlockSparseMatrix mass_matrix(bool lumped) const = 0;
  // True when forces are linear in x (a static solve is then a single linear solve).
  virtual bool is_linear() const = 0;

  // Per-configuration state, e.g. element rotations. x: 3 x n current positions.
  virtual void update(const Nodes& x) = 0;
  // f += internal elastic forces at x (3 x n).
  virtual void add_forces(const Nodes& x, Nodes& f) const = 0;
  // A += scale * K, scattered into a matrix with pattern().
  virtual void add_stiffness(double scale, BlockSparseMatrix& A) const = 0;
  // A += scale * (the exact derivative -df/dx at x, the state of the last update), for
  // Newton solves that want quadratic convergence. Defaults to add_stiffness, which is exact
  // for every model but the co-rotational one (whose R K_e R^T leaves out dR/dx).
  virtual void add_tangent_stiffness(const Nodes& x, double scale, BlockSparseMatrix& A) const {
    add_stiffness(scale, A);
  }
  // f += f(x) - K (y - x): the force linearised about the state of the last update,
  // evaluated at y (3 x n). For the FE models here this is the force formula at y with the
  // rotations of x held fixed, so an implicit step gets its -K v term at no extra cost.
  virtual void add_linearized_forces(const Nodes& y, Nodes& f) const = 0;
  // add_linearized_forces and add_stiffness in one sweep over the elements.
  virtual void add_linearized_forces_and_stiffness(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix& A) const {
    add_linearized_forces(y, f);
    add_stiffness(scale, A);
  }
  // Elastic energy at x (consistent with the forces of the model at its current state).
  virtual double energy(const Nodes& x) const = 0;

  // --- What explicit integration needs; the defaults suit models without damping. ---
  // Point mass per node (n): the lumped mass matrix's diagonal.
  virtual Vec lumped_masses() const;
  // f += elastic forces at x plus the model's own damping forces at velocities v, updating
  // per-configuration state as needed (one call per explicit substep).
  virtual void add_explicit_forces(const Nodes& x, const Nodes& v, Nodes& f) {
    update(x);
    add_forces(x, f);
  }
  virtual bool has_damping() const { return false; }
  // A += scale * C, C = -d f_damping / dv at the last update.
  virtual void add_damping_matrix(double scale, BlockSparseMatrix& A) const {}
  // A += scale * an upper bound of K (resp. C) valid in every configuration, for a stable
  // step that never needs updating. Returns false when the model has none (hyperelastic
  // solids stiffen without bound under stretch).
  virtual bool add_stiffness_bound(double scale, BlockSparseMatrix& A) const { return false; }
  virtual bool add_damping_bound(double scale, BlockSparseMatrix& A) const { return false; }
};

}  // namespace corotate
