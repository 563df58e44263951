#include "corotate/solvers/smoothed_aggregation.hpp"

#include <algorithm>
#include <utility>

namespace corotate {

namespace {

using Block66 = Eigen::Matrix<double, 6, 6>;

// Sums of 3 x 6 blocks keyed by aggregate, for one node row at a time: slot[a] is a's place
// in the row (-1 when absent), reset after each row.
struct RowAccumulator {
  std::vector<int> slot, aggregates;
  Block36List sums;
  explicit RowAccumulator(int num_aggregates) : slot(num_aggregates, -1) {}
  Block36& at(int a) {
    if (slot[a] < 0) {
      slot[a] = static_cast<int>(aggregates.size());
      aggregates.push_back(a);
      if (sums.size() < aggregates.size()) sums.emplace_back();
      sums[slot[a]].setZero();
    }
    return sums[slot[a]];
  }
  // The row's aggregates in ascending order, each with its sum's place.
  std::vector<std::pair<int, int>> sorted() const {
    std::vector<std::pair<int, int>> out;
    out.reserve(aggregates.size());
    for (int a : aggregates) out.emplace_back(a, slot[a]);
    std::sort(out.begin(), out.end());
    return out;
  }
  void clear() {
    for (int a : aggregates) slot[a] = -1;
    aggregates.clear();
  }
};

}  // namespace

NodeAggregateBlocks smoothed_prolongator(const BlockSparseMatrix& A, const std::vector<Mat3>& inverse_diagonal,
                                         const std::vector<int>& aggregate_of_node, const Block36List& tentative,
                                         int num_aggregates, double weight) {
  const Index n = A.num_nodes();
  const auto& start = A.row_start();
  const auto& cols = A.columns();
  NodeAggregateBlocks P;
  P.start.assign(1, 0);
  RowAccumulator row(num_aggregates);
  for (Index i = 0; i < n; ++i) {
    for (int e = start[i]; e < start[i + 1]; ++e) {  // (A T)_i by the aggregates it reaches
      const int j = cols[e];
      row.at(aggregate_of_node[j]).noalias() += A.block(e) * tentative[j];
    }
    for (const auto& [a, k] : row.sorted()) {
      Block36 block = -weight * inverse_diagonal[i] * row.sums[k];
      if (a == aggregate_of_node[i]) block += tentative[i];
      if (block.isZero(0.0)) continue;  // a fixed node's rows, for one
      P.aggregate.push_back(a);
      P.blocks.push_back(block);
    }
    row.clear();
    P.start.push_back(static_cast<int>(P.aggregate.size()));
  }
  return P;
}

Eigen::SparseMatrix<double, Eigen::ColMajor, int> galerkin_product(const BlockSparseMatrix& A,
                                                                   const NodeAggregateBlocks& P,
                                                                   const std::vector<int>& coarse_start) {
  const Index n = A.num_nodes();
  const int m = static_cast<int>(coarse_start.size()) - 1;
  const auto& start = A.row_start();
  const auto& cols = A.columns();

  // 1. The upper blocks (a <= b) of C = P^T A P: b among the aggregates of (A P)_i for some
  // node i whose P row holds a.
  std::vector<std::vector<int>> upper(m);
  RowAccumulator row(m);
  for (Index i = 0; i < n; ++i) {
    for (int e = start[i]; e < start[i + 1]; ++e)
      for (int k = P.start[cols[e]]; k < P.start[cols[e] + 1]; ++k) row.at(P.aggregate[k]);
    for (int k = P.start[i]; k < P.start[i + 1]; ++k) {
      const int a = P.aggregate[k];
      for (int b : row.aggregates)
        if (b >= a) upper[a].push_back(b);
    }
    row.clear();
  }
  std::vector<int> c_start(1, 0), c_column;
  for (int a = 0; a < m; ++a) {
    auto& u = upper[a];
    std::sort(u.begin(), u.end());
    u.erase(std::unique(u.begin(), u.end()), u.end());
    c_column.insert(c_column.end(), u.begin(), u.end());
    c_start.push_back(static_cast<int>(c_column.size()));
    std::vector<int>().swap(u);
  }
  std::vector<Block66, Eigen::aligned_allocator<Block66>> c_blocks(c_column.size(), Block66::Zero());

  // 2. The values, node by node: (A P)_i in the row accumulator, then C_ab += P_ia^T (A P)_ib.
  for (Index i = 0; i < n; ++i) {
    for (int e = start[i]; e < start[i + 1]; ++e) {
      const auto Aij = A.block(e);
      for (int k = P.start[cols[e]]; k < P.start[cols[e] + 1]; ++k)
        row.at(P.aggregate[k]).noalias() += Aij * P.blocks[k];
    }
    for (int k = P.start[i]; k < P.start[i + 1]; ++k) {
      const int a = P.aggregate[k];
      const auto first = c_column.begin() + c_start[a], last = c_column.begin() + c_start[a + 1];
      for (size_t s = 0; s < row.aggregates.size(); ++s) {
        const int b = row.aggregates[s];
        if (b < a) continue;
        const auto at = std::lower_bound(first, last, b) - c_column.begin();
        c_blocks[at].noalias() += P.blocks[k].transpose() * row.sums[s];
      }
    }
    row.clear();
  }

  // 3. The scalar matrix, both triangles: row r of aggregate a holds the blocks (b, a) of the
  // rows b < a transposed, then its own (a, b), b >= a; only the first rank of each aggregate's
  // six rows and columns. Symmetric, so these CSR arrays are its CSC arrays too.
  std::vector<int> lower_start(m + 1, 0), lower_block;
  for (int a = 0; a < m; ++a)
    for (int p = c_start[a]; p < c_start[a + 1]; ++p)
      if (c_column[p] > a) ++lower_start[c_column[p] + 1];
  for (int a = 0; a < m; ++a) lower_start[a + 1] += lower_start[a];
  lower_block.resize(lower_start[m]);
  {
    std::vector<int> next(lower_start.begin(), lower_start.end() - 1);
    for (int a = 0; a < m; ++a)  // rows ascending: each lower list comes out in ascending a
      for (int p = c_start[a]; p < c_start[a + 1]; ++p)
        if (c_column[p] > a) lower_block[next[c_column[p]]++] = p;
  }
  std::vector<int> block_row(c_column.size());  // the aggregate whose row holds each block
  for (int a = 0; a < m; ++a) std::fill(block_row.begin() + c_start[a], block_row.begin() + c_start[a + 1], a);
  const auto rank = [&](int a) { return coarse_start[a + 1] - coarse_start[a]; };
  const int size = coarse_start[m];
  std::vector<int> outer(1, 0), inner;
  std::vector<double> values;
  for (int a = 0; a < m; ++a) {
    for (int r = 0; r < rank(a); ++r) {
      for (int q = lower_start[a]; q < lower_start[a + 1]; ++q) {
        const int p = lower_block[q], b = block_row[p];
        for (int c = 0; c < rank(b); ++c) {
          inner.push_back(coarse_start[b] + c);
          values.push_back(c_blocks[p](c, r));
        }
      }
      for (int p = c_start[a]; p < c_start[a + 1]; ++p) {
        const int b = c_column[p];
        for (int c = 0; c < rank(b); ++c) {
          inner.push_back(coarse_start[b] + c);
          values.push_back(b == a ? 0.5 * (c_blocks[p](r, c) + c_blocks[p](c, r)) : c_blocks[p](r, c));
        }
      }
      outer.push_back(static_cast<int>(inner.size()));
    }
  }
  return Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, int>>(
      size, size, static_cast<Index>(inner.size()), outer.data(), inner.data(), values.data());
}

}  // namespace corotate
