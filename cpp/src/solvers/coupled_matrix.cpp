#include "corotate/solvers/coupled_matrix.hpp"

#include <utility>
#include <vector>

namespace corotate {

BlockSparseMatrix with_coupling(const BlockSparseMatrix& A, const SystemCoupling& coupling) {
  const Index n = A.num_nodes();
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(A.columns().size());
  for (Index i = 0; i < n; ++i)
    for (int k = A.row_start()[i]; k < A.row_start()[i + 1]; ++k)
      if (A.columns()[k] > i) pairs.emplace_back(static_cast<int>(i), A.columns()[k]);
  coupling.for_each_block([&](Index i, Index j, const Mat3&) {
    if (i < j) pairs.emplace_back(static_cast<int>(i), static_cast<int>(j));
  });
  BlockSparseMatrix out = BlockSparseMatrix::from_pairs(n, pairs);
  for (Index i = 0; i < n; ++i)
    for (int k = A.row_start()[i]; k < A.row_start()[i + 1]; ++k)
      out.block(out.block_index(i, A.columns()[k])) = A.block(k);
  coupling.for_each_block([&](Index i, Index j, const Mat3& b) { out.block(out.block_index(i, j)) += b; });
  return out;
}

}  // namespace corotate
