#include "corotate/solvers/block_prolongator.hpp"

#include <algorithm>

#include "corotate/cpu_clones.hpp"
#include "corotate/parallel.hpp"
#include "corotate/simd8.hpp"

// The clones below inline simd8.hpp's helpers: no call passes a vector (see there).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace corotate {

namespace {
constexpr int kRow = 8;                // a block row, and an aggregate's coarse values, padded to eight
constexpr int kBlockValues = 3 * kRow;  // a stored 3 x 6 block
}  // namespace

BlockProlongator::BlockProlongator(const ScalarMatrix& P, const std::vector<int>& coarse_start)
    : coarse_start_(coarse_start) {
  if (P.rows() % 3 != 0) throw InvalidInput("BlockProlongator: the fine size is not a multiple of 3");
  if (coarse_start.empty() || coarse_start.front() != 0 || coarse_start.back() != P.cols())
    throw InvalidInput("BlockProlongator: the aggregates' coarse DOFs do not cover P's columns");
  const Index n = P.rows() / 3, m = num_aggregates();
  std::vector<int> aggregate_of(P.cols());
  for (Index a = 0; a < m; ++a) {
    if (coarse_start[a + 1] < coarse_start[a] || coarse_start[a + 1] - coarse_start[a] > 6)
      throw InvalidInput("BlockProlongator: an aggregate has more than 6 coarse DOFs");
    std::fill(aggregate_of.begin() + coarse_start[a], aggregate_of.begin() + coarse_start[a + 1], int(a));
  }
  node_start_.assign(1, 0);
  std::vector<int> row_aggregates;
  for (Index i = 0; i < n; ++i) {
    row_aggregates.clear();
    for (int r = 0; r < 3; ++r)
      for (ScalarMatrix::InnerIterator it(P, 3 * i + r); it; ++it) row_aggregates.push_back(aggregate_of[it.col()]);
    std::sort(row_aggregates.begin(), row_aggregates.end());
    row_aggregates.erase(std::unique(row_aggregates.begin(), row_aggregates.end()), row_aggregates.end());
    const size_t first = block_aggregate_.size();
    block_aggregate_.insert(block_aggregate_.end(), row_aggregates.begin(), row_aggregates.end());
    values_.resize(kBlockValues * block_aggregate_.size(), 0.0f);
    for (int r = 0; r < 3; ++r)
      for (ScalarMatrix::InnerIterator it(P, 3 * i + r); it; ++it) {
        const int a = aggregate_of[it.col()];
        const size_t k =
            first + (std::lower_bound(row_aggregates.begin(), row_aggregates.end(), a) - row_aggregates.begin());
        values_[kBlockValues * k + kRow * r + (it.col() - coarse_start[a])] = static_cast<float>(it.value());
      }
    node_start_.push_back(static_cast<int>(block_aggregate_.size()));
  }
  index_by_aggregate();
}

BlockProlongator::BlockProlongator(const NodeAggregateBlocks& P, const std::vector<int>& coarse_start)
    : coarse_start_(coarse_start), node_start_(P.start), block_aggregate_(P.aggregate) {
  if (coarse_start.empty() || coarse_start.front() != 0 || P.start.empty() || P.start.back() != int(P.blocks.size()))
    throw InvalidInput("BlockProlongator: the blocks or the aggregates' coarse DOFs are malformed");
  values_.assign(kBlockValues * P.blocks.size(), 0.0f);
  for (size_t k = 0; k < P.blocks.size(); ++k) {
    const int a = P.aggregate[k];
    if (a < 0 || a >= num_aggregates()) throw InvalidInput("BlockProlongator: a block's aggregate is out of range");
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < coarse_start[a + 1] - coarse_start[a]; ++c)
        values_[kBlockValues * k + kRow * r + c] = static_cast<float>(P.blocks[k](r, c));
  }
  index_by_aggregate();
}

void BlockProlongator::index_by_aggregate() {
  // Per aggregate, its blocks in node order (a counting sort of the blocks by aggregate).
  const Index n = num_nodes(), m = num_aggregates();
  aggregate_start_.assign(m + 1, 0);
  for (int a : block_aggregate_) ++aggregate_start_[a + 1];
  for (Index a = 0; a < m; ++a) aggregate_start_[a + 1] += aggregate_start_[a];
  aggregate_block_.resize(block_aggregate_.size());
  aggregate_node_.resize(block_aggregate_.size());
  std::vector<int> next(aggregate_start_.begin(), aggregate_start_.end() - 1);
  for (Index i = 0; i < n; ++i)
    for (int k = node_start_[i]; k < node_start_[i + 1]; ++k) {
      const int slot = next[block_aggregate_[k]]++;
      aggregate_block_[slot] = k;
      aggregate_node_[slot] = static_cast<int>(i);
    }
  padded_.setZero(kRow * m);
}

Eigen::Matrix<double, 3, 6> BlockProlongator::block(int k) const {
  Eigen::Matrix<double, 3, 6> out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 6; ++c) out(r, c) = values_[kBlockValues * size_t(k) + kRow * r + c];
  return out;
}

// Both products take a block row and an aggregate's eight padded coarse values as one
// eight-wide vector each (the padding is zero on both sides): three multiply-adds per block,
// where the 3 x 6 scalar loop compiled to shuffles around four-wide pieces (9.5 % of a step
// at 15,360 tets for the two).
COROTATE_CPU_CLONES void BlockProlongator::prolong(const Vec& coarse, Vec& fine, bool add) {
  const Index n = num_nodes(), m = num_aggregates();
  for (Index a = 0; a < m; ++a)
    for (int q = 0; q < 6; ++q)
      padded_[kRow * a + q] = q < coarse_start_[a + 1] - coarse_start_[a] ? float(coarse[coarse_start_[a] + q]) : 0.0f;
  fine.resize(3 * n);
  const float* c = padded_.data();
  const float* val = values_.data();
  double* y = fine.data();
  COROTATE_PARALLEL_FOR(n >= 512)
  for (Index i = 0; i < n; ++i) {
    double y0 = 0, y1 = 0, y2 = 0;
#if defined(COROTATE_HAVE_FLOAT8)
    using namespace simd;
    Float8 s0 = {}, s1 = {}, s2 = {};
    for (int k = node_start_[i]; k < node_start_[i + 1]; ++k) {
      const float* b = val + kBlockValues * k;
      const Float8 ca = load8(c + kRow * block_aggregate_[k]);
      s0 += load8(b) * ca;
      s1 += load8(b + kRow) * ca;
      s2 += load8(b + 2 * kRow) * ca;
    }
    y0 = sum8(s0), y1 = sum8(s1), y2 = sum8(s2);
#else
    float s0 = 0, s1 = 0, s2 = 0;
    for (int k = node_start_[i]; k < node_start_[i + 1]; ++k) {
      const float* b = val + kBlockValues * k;
      const float* ca = c + kRow * block_aggregate_[k];
      for (int q = 0; q < 6; ++q) {
        s0 += b[q] * ca[q];
        s1 += b[kRow + q] * ca[q];
        s2 += b[2 * kRow + q] * ca[q];
      }
    }
    y0 = s0, y1 = s1, y2 = s2;
#endif
    y[3 * i] = (add ? y[3 * i] : 0.0) + y0;
    y[3 * i + 1] = (add ? y[3 * i + 1] : 0.0) + y1;
    y[3 * i + 2] = (add ? y[3 * i + 2] : 0.0) + y2;
  }
}

namespace {
// ca += the block's rows times r0, r1, r2 (eight values, the padding stays zero).
COROTATE_CLONE_INLINE void add_restricted(const float* b, float r0, float r1, float r2, float* ca) {
#if defined(COROTATE_HAVE_FLOAT8)
  using namespace simd;
  add8(ca, load8(b) * r0 + load8(b + kRow) * r1 + load8(b + 2 * kRow) * r2);  // scalar times vector: a broadcast
#else
  for (int q = 0; q < 6; ++q) ca[q] += b[q] * r0 + b[kRow + q] * r1 + b[2 * kRow + q] * r2;
#endif
}
}  // namespace

COROTATE_CPU_CLONES void BlockProlongator::restrict_to(const Vec& fine, Vec& coarse) {
  const Index n = num_nodes(), m = num_aggregates();
  const double* r = fine.data();
  const float* val = values_.data();
  float* c = padded_.data();
  if (num_threads() == 1 || m < 64) {
    // Streaming the blocks in storage order and scattering into the aggregates reads them
    // faster than the gather; each aggregate still sums its blocks in node order, the same
    // sum as the gather's, so the bits do not depend on the thread count.
    padded_.setZero();
    for (Index i = 0; i < n; ++i) {
      const float r0 = float(r[3 * i]), r1 = float(r[3 * i + 1]), r2 = float(r[3 * i + 2]);
      for (int k = node_start_[i]; k < node_start_[i + 1]; ++k)
        add_restricted(val + kBlockValues * k, r0, r1, r2, c + kRow * block_aggregate_[k]);
    }
  } else {
    COROTATE_PARALLEL_FOR(true)
    for (Index a = 0; a < m; ++a) {
      alignas(32) float ca[kRow] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (int s = aggregate_start_[a]; s < aggregate_start_[a + 1]; ++s) {
        const double* ri = r + 3 * aggregate_node_[s];
        add_restricted(val + kBlockValues * aggregate_block_[s], float(ri[0]), float(ri[1]), float(ri[2]), ca);
      }
      for (int q = 0; q < kRow; ++q) c[kRow * a + q] = ca[q];
    }
  }
  coarse.resize(coarse_size());
  for (Index a = 0; a < m; ++a)
    for (int q = 0; q < coarse_start_[a + 1] - coarse_start_[a]; ++q)
      coarse[coarse_start_[a] + q] = padded_[kRow * a + q];
}

}  // namespace corotate
