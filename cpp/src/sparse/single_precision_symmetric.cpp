#include "corotate/sparse/single_precision_symmetric.hpp"

#include <algorithm>
#include <cmath>

#include "corotate/cpu_clones.hpp"
#include "corotate/parallel.hpp"
#include "corotate/sparse/symmetric_product.hpp"

namespace corotate {

namespace {
// out[k] = scale * [first, last)[k] in float; returns the end of what it wrote.
COROTATE_CLONE_INLINE float* convert(const double* first, const double* last, double scale, float* out) {
  for (; first != last; ++first, ++out) *out = static_cast<float>(scale * *first);
  return out;
}
}  // namespace

void SinglePrecisionSymmetric::build_layout(const BlockSparseMatrix& A) {
  const Index n = A.num_nodes();
  chunk_start_ = A.chunk_start();
  row_first_.assign(1, 0);
  diagonal_.resize(n);
  chunk_end_.resize(n);
  columns_.clear();
  const auto& cols = A.columns();
  for (Index i = 0; i < n; ++i) {  // the product runs, the diagonal first in the second
    const auto [lower, upper] = A.product_runs(i);
    columns_.insert(columns_.end(), cols.begin() + lower.first, cols.begin() + lower.second);
    diagonal_[i] = static_cast<int>(columns_.size());
    columns_.insert(columns_.end(), cols.begin() + upper.first, cols.begin() + upper.second);
    chunk_end_[i] = diagonal_[i] + (A.chunk_upper(i) - upper.first);
    row_first_.push_back(static_cast<int>(columns_.size()));
  }
  values_.assign(9 * columns_.size() + 4, 0.0f);  // padding: a block row's four-wide load
  pattern_rows_ = A.row_start();
  pattern_columns_ = A.columns().data();
  pattern_blocks_ = A.num_blocks();
}

COROTATE_CPU_CLONES void SinglePrecisionSymmetric::assign(const BlockSparseMatrix& A) {
  // Same pattern: the same arrays (not a new matrix that reuses freed memory: the row
  // starts must match too, a cheap n-int comparison next to the 9-values-per-block copy).
  if (A.columns().data() != pattern_columns_ || A.num_blocks() != pattern_blocks_ || A.row_start() != pattern_rows_)
    build_layout(A);
  // The largest diagonal entry bounds every entry of a positive definite matrix, and the
  // scale needs only be about right: a power of two, so scaling and unscaling are exact. A
  // zero or non-finite diagonal keeps 1 (non-finite values reach the product as in double).
  const double* src = A.values().data();
  double largest = 0.0;
  for (Index i = 0, n = num_nodes(); i < n; ++i) {
    const double* d = src + 9 * A.diagonal_block(i);
    largest = std::max({largest, std::abs(d[0]), std::abs(d[4]), std::abs(d[8])});
  }
  int exponent = 0;
  if (largest > 0 && std::isfinite(largest)) std::frexp(largest, &exponent);
  unscale_ = std::ldexp(1.0, exponent);
  const double scale = std::ldexp(1.0, -exponent);
  // Row by row, the stored blocks are A's two product runs; each converts as one flat loop.
  float* dst = values_.data();
  const Index chunks = static_cast<Index>(chunk_start_.size()) - 1;
  COROTATE_PARALLEL_FOR(chunks > 1)
  for (Index c = 0; c < chunks; ++c)
    for (int i = chunk_start_[c]; i < chunk_start_[c + 1]; ++i) {
      float* out = dst + 9 * row_first_[i];
      for (const auto& [begin, end] : A.product_runs(i)) out = convert(src + 9 * begin, src + 9 * end, scale, out);
    }
}

// BlockSparseMatrix::multiply_symmetric's rows over the float copy: the blocks across chunks
// below the diagonal come first, so they end where the diagonal is.
COROTATE_CPU_CLONES void SinglePrecisionSymmetric::kernel(const double* xp, double* yp) const {
  const SymmetricRows rows{row_first_.data(), diagonal_.data(), diagonal_.data(), chunk_end_.data()};
  const Index chunks = static_cast<Index>(chunk_start_.size()) - 1;
  COROTATE_PARALLEL_FOR(chunks > 1)
  for (Index c = 0; c < chunks; ++c)
    symmetric_chunk(values_.data(), columns_.data(), rows, chunk_start_[c], chunk_start_[c + 1], xp, yp);
}

void SinglePrecisionSymmetric::multiply(const Vec& x, Vec& y) const {
  padded_product(x, y, [this](const double* x4, double* y4) { kernel(x4, y4); }, unscale_);
}

}  // namespace corotate
