#include "corotate/sparse/block_sparse_matrix.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "corotate/cpu_clones.hpp"
#include "corotate/parallel.hpp"
#include "corotate/sparse/symmetric_product.hpp"

namespace corotate {

BlockSparseMatrix BlockSparseMatrix::from_pairs(Index num_nodes, const std::vector<std::pair<int, int>>& pairs) {
  std::vector<std::vector<int>> adjacency(num_nodes);
  for (Index i = 0; i < num_nodes; ++i) adjacency[i].push_back(static_cast<int>(i));
  for (const auto& [i, j] : pairs) {
    adjacency[i].push_back(j);
    adjacency[j].push_back(i);
  }
  BlockSparseMatrix m;
  m.row_start_.assign(1, 0);
  m.diagonal_.resize(num_nodes);
  for (Index i = 0; i < num_nodes; ++i) {
    auto& row = adjacency[i];
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    for (int j : row) {
      if (j == i) m.diagonal_[i] = static_cast<int>(m.columns_.size());
      m.columns_.push_back(j);
    }
    m.row_start_.push_back(static_cast<int>(m.columns_.size()));
  }
  m.values_.assign(9 * m.columns_.size(), 0.0);

  // About num_nodes / 512 chunks, at most 8: enough for the threads of a small machine, few
  // enough that most coupled pairs of a well-ordered mesh fall inside one chunk.
  const Index chunks = std::clamp<Index>(num_nodes / 512, 1, 8);
  for (Index c = 0; c <= chunks; ++c) m.chunk_start_.push_back(static_cast<int>(c * num_nodes / chunks));
  m.chunk_lower_.resize(num_nodes);
  m.chunk_upper_.resize(num_nodes);
  for (Index c = 0; c < chunks; ++c)
    for (int i = m.chunk_start_[c]; i < m.chunk_start_[c + 1]; ++i) {
      int k = m.row_start_[i];
      while (m.columns_[k] < m.chunk_start_[c]) ++k;
      m.chunk_lower_[i] = k;
      k = m.row_start_[i + 1];
      while (m.columns_[k - 1] >= m.chunk_start_[c + 1]) --k;
      m.chunk_upper_[i] = k;
    }
  return m;
}

BlockSparseMatrix BlockSparseMatrix::from_cells(Index num_nodes, const Connectivity& cells) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(cells.rows() * cells.cols() * (cells.cols() - 1) / 2);
  for (Index e = 0; e < cells.rows(); ++e)
    for (Index a = 0; a < cells.cols(); ++a)
      for (Index b = a + 1; b < cells.cols(); ++b) pairs.emplace_back(cells(e, a), cells(e, b));
  return from_pairs(num_nodes, pairs);
}

int BlockSparseMatrix::block_index(Index i, Index j) const {
  const auto first = columns_.begin() + row_start_[i], last = columns_.begin() + row_start_[i + 1];
  const auto it = std::lower_bound(first, last, static_cast<int>(j));
  return (it != last && *it == j) ? static_cast<int>(it - columns_.begin()) : -1;
}

void BlockSparseMatrix::set_zero() { std::fill(values_.begin(), values_.end(), 0.0); }

void BlockSparseMatrix::assign_scaled(double a, const BlockSparseMatrix& other, bool lower_blocks) {
  const double* src = other.values_.data();
  double* dst = values_.data();
  auto run = [&](int first, int last) {  // blocks [first, last)
    for (int k = 9 * first; k < 9 * last; ++k) dst[k] = a * src[k];
  };
  // By row chunks, threaded: a pass over the whole matrix, as long as a product's.
  const Index chunks = num_chunks();
  COROTATE_PARALLEL_FOR(chunks > 1)
  for (Index c = 0; c < chunks; ++c) {
    const int first = chunk_start_[c], last = chunk_start_[c + 1];
    if (lower_blocks) {
      run(row_start_[first], row_start_[last]);
      continue;
    }
    for (int i = first; i < last; ++i)
      for (const auto& [begin, end] : product_runs(i)) run(begin, end);
  }
}

void BlockSparseMatrix::mirror_upper_blocks() {
  for (Index i = 0; i < num_nodes(); ++i)
    for (int k = chunk_lower_[i]; k < diagonal_[i]; ++k)  // (the blocks is_product_block skips)
      block(k) = block(block_index(columns_[k], i)).transpose();
}

void BlockSparseMatrix::multiply(const Vec& x, Vec& y) const {
  const Index n = num_nodes();
  const double* val = values_.data();
  const double* xp = x.data();
  double* yp = y.data();
  // Rows are independent: each thread writes its own range of y.
  COROTATE_PARALLEL_FOR(n >= 512)
  for (Index i = 0; i < n; ++i) {
    double y0 = 0, y1 = 0, y2 = 0;
    for (int k = row_start_[i]; k < row_start_[i + 1]; ++k) {
      const double* b = val + 9 * k;
      const double* xj = xp + 3 * columns_[k];
      y0 += b[0] * xj[0] + b[1] * xj[1] + b[2] * xj[2];
      y1 += b[3] * xj[0] + b[4] * xj[1] + b[5] * xj[2];
      y2 += b[6] * xj[0] + b[7] * xj[1] + b[8] * xj[2];
    }
    yp[3 * i] = y0;
    yp[3 * i + 1] = y1;
    yp[3 * i + 2] = y2;
  }
}

COROTATE_CPU_CLONES void BlockSparseMatrix::symmetric_kernel(const double* xp, double* yp) const {
  const SymmetricRows rows{row_start_.data(), chunk_lower_.data(), diagonal_.data(), chunk_upper_.data()};
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

void BlockSparseMatrix::multiply_symmetric(const Vec& x, Vec& y) const {
  padded_product(x, y, [this](const double* x4, double* y4) { symmetric_kernel(x4, y4); });
}

bool BlockSparseMatrix::is_symmetric(double relative_tolerance) const {
  double largest = 0.0;
  for (double v : values_) largest = std::max(largest, std::abs(v));
  const double tolerance = relative_tolerance * largest;
  for (Index i = 0; i < num_nodes(); ++i)
    for (int k = row_start_[i]; k < row_start_[i + 1]; ++k) {
      const int t = block_index(columns_[k], i);
      if (t < 0 || !((block(k) - block(t).transpose()).cwiseAbs().maxCoeff() <= tolerance)) return false;
    }
  return true;
}

void BlockSparseMatrix::copy_to(Eigen::SparseMatrix<double, Eigen::ColMajor, int>& out) const {
  const Index n = num_nodes(), dofs = num_dofs();
  if (out.rows() != dofs || out.nonZeros() != static_cast<Index>(values_.size())) {
    // Build the scalar pattern once: scalar row 3i+r holds, per block (i, j), columns 3j..3j+2.
    out.resize(dofs, dofs);
    out.resizeNonZeros(static_cast<Index>(values_.size()));
    int* outer = out.outerIndexPtr();
    int* inner = out.innerIndexPtr();
    int pos = 0;
    for (Index i = 0; i < n; ++i)
      for (int r = 0; r < 3; ++r) {
        outer[3 * i + r] = pos;
        for (int k = row_start_[i]; k < row_start_[i + 1]; ++k)
          for (int c = 0; c < 3; ++c) inner[pos++] = 3 * columns_[k] + c;
      }
    outer[dofs] = pos;
  }
  double* dst = out.valuePtr();
  int pos = 0;
  for (Index i = 0; i < n; ++i)
    for (int r = 0; r < 3; ++r)
      for (int k = row_start_[i]; k < row_start_[i + 1]; ++k)
        for (int c = 0; c < 3; ++c) dst[pos++] = values_[9 * k + 3 * r + c];
}

}  // namespace corotate
