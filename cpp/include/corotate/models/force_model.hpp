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
  // Both at once; models override this when one sweep over the elements is cheaper.
  virtual void add_forces_and_stiffness(const Nodes& x, Nodes& f, double scale, BlockSparseMatrix& A) const {
    add_forces(x, f);
    add_stiffness(scale, A);
  }
  // Elastic energy at x (consistent with the forces of the model at its current state).
  virtual double energy(const Nodes& x) const = 0;
};

}  // namespace corotate
