// Fixed degrees of freedom imposed on a linear system A dx = b by projection: the rows and
// columns of fixed DOFs are zeroed and their diagonal set to one, their right-hand side to
// zero, so the solution is zero there and the matrix stays symmetric positive definite.
// The value indices that this touches are found once, when the fixed set changes.
#pragma once

#include <vector>

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class SinglePrecisionSymmetric;

class FixedDofs {
 public:
  FixedDofs() = default;
  // fixed: one flag per DOF (3 * num_nodes), nonzero = fixed.
  FixedDofs(const BlockSparseMatrix& pattern, const std::vector<char>& fixed);

  bool empty() const { return fixed_list_.empty(); }
  const std::vector<Index>& list() const { return fixed_list_; }
  void project(BlockSparseMatrix& A) const;
  // The same on a float32 system in the pattern FixedDofs was made for (its stored blocks).
  void project(SinglePrecisionSymmetric& A) const;
  void project(Eigen::Ref<Vec> b) const;  // b: one entry per DOF
  void project(Nodes& x) const { project(as_dofs(x)); }

 private:
  std::vector<Index> fixed_list_;   // DOF indices
  std::vector<int> zero_values_;    // value indices to zero
  std::vector<int> unit_values_;    // value indices of fixed diagonal entries
};

}  // namespace corotate
