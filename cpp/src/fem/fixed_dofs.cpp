#include "corotate/fem/fixed_dofs.hpp"

#include <algorithm>

#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate {

FixedDofs::FixedDofs(const BlockSparseMatrix& pattern, const std::vector<char>& fixed) {
  const auto& start = pattern.row_start();
  const auto& cols = pattern.columns();
  for (Index d = 0; d < static_cast<Index>(fixed.size()); ++d)
    if (fixed[d]) fixed_list_.push_back(d);
  // Only the blocks in the rows of nodes with a fixed DOF and their mirror images (the
  // pattern is symmetric) are touched: visiting just those keeps a change of the fixed set
  // cheap on a large mesh.
  auto classify = [&](int k, Index row_node, Index col_node) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        const bool row_fixed = fixed[3 * row_node + r], col_fixed = fixed[3 * col_node + c];
        if (!row_fixed && !col_fixed) continue;
        const int v = 9 * k + 3 * r + c;
        if (row_fixed && col_node == row_node && r == c) unit_values_.push_back(v);
        else zero_values_.push_back(v);
      }
  };
  for (Index i = 0; i < pattern.num_nodes(); ++i) {
    if (!fixed[3 * i] && !fixed[3 * i + 1] && !fixed[3 * i + 2]) continue;
    for (int k = start[i]; k < start[i + 1]; ++k) {
      const Index j = cols[k];
      classify(k, i, j);
      if (j != i) classify(pattern.block_index(j, i), j, i);
    }
  }
  // Both nodes of a block may be fixed: each value once.
  for (auto* values : {&zero_values_, &unit_values_}) {
    std::sort(values->begin(), values->end());
    values->erase(std::unique(values->begin(), values->end()), values->end());
  }
}

void FixedDofs::project(BlockSparseMatrix& A) const {
  auto& values = A.values();
  for (int v : zero_values_) values[v] = 0.0;
  for (int v : unit_values_) values[v] = 1.0;
}

void FixedDofs::project(SinglePrecisionSymmetric& A) const {
  float* values = A.values();
  // A value index 9 k + e of the pattern is entry e of its block k, stored or not.
  auto stored = [&](int v) {
    const int block = A.block_position(v / 9);
    return block < 0 ? nullptr : values + 9 * block + v % 9;
  };
  for (int v : zero_values_)
    if (float* p = stored(v)) *p = 0.0f;
  const auto one = static_cast<float>(1.0 / A.unscale());  // a power of two: exact
  for (int v : unit_values_)
    if (float* p = stored(v)) *p = one;
}

void FixedDofs::project(Eigen::Ref<Vec> b) const {
  for (Index d : fixed_list_) b[d] = 0.0;
}

}  // namespace corotate
