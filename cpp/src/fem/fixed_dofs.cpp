#include "corotate/fem/fixed_dofs.hpp"

#include <algorithm>

namespace corotate {

FixedDofs::FixedDofs(const BlockSparseMatrix& pattern, const std::vector<char>& fixed) {
  const auto& start = pattern.row_start();
  const auto& cols = pattern.columns();
  for (Index d = 0; d < static_cast<Index>(fixed.size()); ++d)
    if (fixed[d]) fixed_list_.push_back(d);
  for (Index i = 0; i < pattern.num_nodes(); ++i)
    for (int k = start[i]; k < start[i + 1]; ++k)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const bool row_fixed = fixed[3 * i + r], col_fixed = fixed[3 * cols[k] + c];
          if (!row_fixed && !col_fixed) continue;
          const int v = 9 * k + 3 * r + c;
          if (row_fixed && cols[k] == i && r == c) unit_values_.push_back(v);
          else zero_values_.push_back(v);
        }
}

void FixedDofs::project(BlockSparseMatrix& A) const {
  auto& values = A.values();
  for (int v : zero_values_) values[v] = 0.0;
  for (int v : unit_values_) values[v] = 1.0;
}

void FixedDofs::project(Eigen::Ref<Vec> b) const {
  for (Index d : fixed_list_) b[d] = 0.0;
}

}  // namespace corotate
