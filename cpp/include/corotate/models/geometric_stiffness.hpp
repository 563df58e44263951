// Models that can give their initial-stress (geometric) stiffness on its own, the K_sigma of
// K_T = K_0 + K_u + K_sigma (paper eq. 6):
//     K_sigma,ab = sum over quadrature points of w (G_a^T S G_b) I_3,
// S the second Piola-Kirchhoff stress at the given positions, G_a = dN_a/dX. It is the part
// of the tangent that a stress state contributes by itself (e.g. the stiffening of a
// pre-tensioned string), needed later by modal reduction around a loaded state.
#pragma once

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class GeometricStiffness {
 public:
  virtual ~GeometricStiffness() = default;
  // A += scale * K_sigma(x), A with the model's pattern(). x: 3 x n positions.
  virtual void add_geometric_stiffness(const Nodes& x, double scale, BlockSparseMatrix& A) const = 0;
};

}  // namespace corotate
