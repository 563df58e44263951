#include "corotate/models/force_model.hpp"

namespace corotate {

Vec ForceModel::lumped_masses() const {
  const BlockSparseMatrix M = mass_matrix(true);
  Vec m(num_nodes());
  for (Index i = 0; i < num_nodes(); ++i) m[i] = M.block(M.diagonal_block(i))(0, 0);
  return m;
}

}  // namespace corotate
