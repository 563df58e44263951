// SupernodalCholesky::factorize: multifrontal numeric factorization (supernodal_cholesky.hpp).
#include <algorithm>
#include <cstring>

#include "corotate/solvers/dense_kernels.hpp"
#include "corotate/solvers/supernodal_cholesky.hpp"

namespace corotate {

bool SupernodalCholesky::factorize(const Matrix& A) {
  if (A.rows() != view_.n || A.nonZeros() != analysed_nonzeros_ || !A.isCompressed())
    throw InvalidInput("supernodal Cholesky: the matrix's pattern is not the analysed one");
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* a = A.valuePtr();
  for (int s = 0; s < view_.nsuper; ++s) {
    const int f = super_[s], k = super_[s + 1] - f, m = pi_[s + 1] - pi_[s], below = m - k;
    const int* rows = rows_.data() + pi_[s];
    for (int t = 0; t < m; ++t) relative_[rows[t]] = t;
    // The front: the panel (its first k columns, in the factor's place) and the update matrix
    // U (the rest), which starts on the stack above the children's updates.
    double* panel = values_.data() + px_[s];
    std::fill(panel, panel + static_cast<size_t>(m) * k, 0.0);
    double* const children = stack_.data() + children_start_[s];
    double* const U = stack_.data() + update_start_[s];
    std::fill(U, U + static_cast<size_t>(below) * below, 0.0);
    // A's entries on and below the diagonal of the front's columns.
    for (int j = f; j < f + k; ++j) {
      double* column = panel + static_cast<size_t>(j - f) * m;
      for (int p = outer[perm_[j]]; p < outer[perm_[j] + 1]; ++p) {
        const int i = inverse_perm_[inner[p]];
        if (i >= j) column[relative_[i]] += a[p];
      }
    }
    // Extend-add of the children's update matrices (their rows are among the front's).
    const double* update = children;
    for (int c = first_child_[s]; c >= 0; c = next_sibling_[c]) {
      const int kc = super_[c + 1] - super_[c], bc = pi_[c + 1] - pi_[c] - kc;
      const int* child_rows = rows_.data() + pi_[c] + kc;
      for (int t = 0; t < bc; ++t) map_[t] = relative_[child_rows[t]];
      for (int col = 0; col < bc; ++col) {
        const int target = map_[col];
        double* dst =
            target < k ? panel + static_cast<size_t>(target) * m : U + static_cast<size_t>(target - k) * below - k;
        const double* src = update + static_cast<size_t>(col) * bc;
        for (int r = col; r < bc; ++r) dst[map_[r]] += src[r];
      }
      update += static_cast<size_t>(bc) * bc;
    }
    if (!factor_panel(panel, m, k)) return false;
    if (below > 0) {
      subtract_lower_product(panel + k, m, below, k, U);
      std::memmove(children, U, sizeof(double) * below * below);
    }
  }
  return true;
}

}  // namespace corotate
