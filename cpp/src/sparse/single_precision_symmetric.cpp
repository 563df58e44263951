#include "corotate/sparse/single_precision_symmetric.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

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
  block_position_.assign(A.num_blocks(), -1);
  for (Index i = 0; i < n; ++i) {  // the product runs, the diagonal first in the second
    const auto [lower, upper] = A.product_runs(i);
    for (int k = lower.first; k < lower.second; ++k)
      block_position_[k] = static_cast<int>(columns_.size()) + k - lower.first;
    columns_.insert(columns_.end(), cols.begin() + lower.first, cols.begin() + lower.second);
    diagonal_[i] = static_cast<int>(columns_.size());
    for (int k = upper.first; k < upper.second; ++k) block_position_[k] = diagonal_[i] + k - upper.first;
    columns_.insert(columns_.end(), cols.begin() + upper.first, cols.begin() + upper.second);
    chunk_end_[i] = diagonal_[i] + (A.chunk_upper(i) - upper.first);
    row_first_.push_back(static_cast<int>(columns_.size()));
  }
  values_.assign(9 * columns_.size() + 4, 0.0f);  // padding: a block row's four-wide load
  pattern_rows_ = A.row_start();
  pattern_columns_ = A.columns().data();
  pattern_blocks_ = A.num_blocks();
  static std::atomic<std::uint64_t> layouts{0};
  layout_id_ = ++layouts;
}

COROTATE_CPU_CLONES void SinglePrecisionSymmetric::convert_from(const BlockSparseMatrix& A, double scale,
                                                                float* dst) const {
  // Row by row, the stored blocks are A's two product runs; each converts as one flat loop.
  const double* src = A.values().data();
  const Index chunks = static_cast<Index>(chunk_start_.size()) - 1;
  COROTATE_PARALLEL_FOR(chunks > 1)
  for (Index c = 0; c < chunks; ++c)
    for (int i = chunk_start_[c]; i < chunk_start_[c + 1]; ++i) {
      float* out = dst + 9 * row_first_[i];
      for (const auto& [begin, end] : A.product_runs(i)) out = convert(src + 9 * begin, src + 9 * end, scale, out);
    }
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
  convert_from(A, std::ldexp(1.0, -exponent), values_.data());
  ++assemblies_;
}

void SinglePrecisionSymmetric::restore_values(const std::vector<float>& from) {
  if (from.size() != values_.size()) throw InvalidInput("float32 system: restoring values of another layout");
  std::memcpy(values_.data(), from.data(), values_.size() * sizeof(float));
  ++assemblies_;
}

void SinglePrecisionSymmetric::start_assembly(const BlockSparseMatrix& M, double s, std::uint64_t version) {
  if (s != start_s_ || unscale_ != start_unscale_ || version != start_version_ || layout_id_ != start_layout_) {
    // (The pattern is checked only here: the caller's version number stands for M.)
    if (!has_layout() || M.num_blocks() != pattern_blocks_ || M.row_start() != pattern_rows_ ||
        !std::equal(M.columns().begin(), M.columns().end(), pattern_columns_))
      throw InvalidInput("float32 assembly: the starting matrix is not in the pattern of the system's layout");
    start_values_.assign(values_.size(), 0.0f);  // the padding stays zero
    convert_from(M, s / unscale_, start_values_.data());
    start_s_ = s, start_unscale_ = unscale_, start_version_ = version, start_layout_ = layout_id_;
  }
  std::memcpy(values_.data(), start_values_.data(), values_.size() * sizeof(float));
  ++assemblies_;
}

void SinglePrecisionSymmetric::add_to_diagonal(Index i, double value) {
  float* d = values_.data() + 9 * diagonal_[i];
  for (int r = 0; r < 3; ++r) d[4 * r] = static_cast<float>(d[4 * r] + value / unscale_);
}

void SinglePrecisionSymmetric::add_to_diagonal_block(Index i, const Mat3& value) {
  float* d = values_.data() + 9 * diagonal_[i];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d[3 * r + c] = static_cast<float>(d[3 * r + c] + value(r, c) / unscale_);
}

Mat3 SinglePrecisionSymmetric::diagonal_block(Index i) const {
  const float* d = values_.data() + 9 * diagonal_[i];
  Mat3 block;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) block(r, c) = unscale_ * d[3 * r + c];
  return block;
}

// BlockSparseMatrix::multiply_symmetric's rows over the float copy: the blocks across chunks
// below the diagonal come first, so they end where the diagonal is.
COROTATE_CPU_CLONES void SinglePrecisionSymmetric::kernel(const float* xp, float* yp) const {
  const SymmetricRows rows{row_first_.data(), diagonal_.data(), diagonal_.data(), chunk_end_.data()};
  const Index chunks = static_cast<Index>(chunk_start_.size()) - 1;
  if (runs_in_parallel(chunks > 1)) {
    COROTATE_PARALLEL_FOR(true)
    for (Index c = 0; c < chunks; ++c)
      symmetric_chunk(values_.data(), columns_.data(), rows, chunk_start_[c], chunk_start_[c + 1], xp, yp);
  } else {
    for (Index c = 0; c < chunks; ++c)
      symmetric_chunk(values_.data(), columns_.data(), rows, chunk_start_[c], chunk_start_[c + 1], xp, yp);
  }
}

void SinglePrecisionSymmetric::multiply(const Vec& x, Vec& y) const {
  padded_product<float>(x, y, [this](const float* x4, float* y4) { kernel(x4, y4); }, unscale_);
}

}  // namespace corotate
