// Symmetric sparse matrix stored as 3x3 blocks (one block per pair of coupled nodes).
//
// The pattern is built once from the element connectivity; both triangles are stored so a
// matrix-vector product is a plain row sweep. Each element keeps the indices of its blocks
// (see block_index), so assembly is a scatter-add with no search and no allocation.
#pragma once

#include <Eigen/SparseCore>
#include <array>
#include <utility>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

class BlockSparseMatrix {
 public:
  using Block = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;
  using ConstBlock = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;

  BlockSparseMatrix() = default;

  // Pattern coupling every pair of nodes that share a cell. cells: m x k node indices.
  static BlockSparseMatrix from_cells(Index num_nodes, const Connectivity& cells);
  // Pattern from an explicit list of coupled node pairs (i, j); the diagonal is always present.
  static BlockSparseMatrix from_pairs(Index num_nodes, const std::vector<std::pair<int, int>>& pairs);

  Index num_nodes() const { return static_cast<Index>(row_start_.size()) - 1; }
  Index num_dofs() const { return 3 * num_nodes(); }
  Index num_blocks() const { return static_cast<Index>(columns_.size()); }

  // Index of block (i, j) in the value array; -1 if not in the pattern. O(log row length):
  // meant for precomputation only.
  int block_index(Index i, Index j) const;
  int diagonal_block(Index i) const { return diagonal_[i]; }

  Block block(int k) { return Block(values_.data() + 9 * k); }
  ConstBlock block(int k) const { return ConstBlock(values_.data() + 9 * k); }
  std::vector<double>& values() { return values_; }
  const std::vector<double>& values() const { return values_; }
  const std::vector<int>& row_start() const { return row_start_; }
  const std::vector<int>& columns() const { return columns_; }

  void set_zero();
  // this = a * other (same pattern); no allocation. With lower_blocks false only the blocks
  // multiply_symmetric reads (is_product_block) are assigned; the rest keep what they held.
  void assign_scaled(double a, const BlockSparseMatrix& other, bool lower_blocks = true);
  // The blocks multiply_symmetric does not read, set to the transposes of their mirrors: a
  // matrix assembled with lower_blocks false made whole for a factorization. O(blocks log
  // row length): for the rare step that needs it.
  void mirror_upper_blocks();
  // y = A x (x, y: num_dofs()).
  void multiply(const Vec& x, Vec& y) const;
  // y = A x for an exactly symmetric A (the system matrices of a step: assembly mirrors each
  // block, FixedDofs zeroes rows and columns alike), reading about half the bytes: within a
  // row chunk each pair (i, j), j > i, is read once from the upper block and used twice,
  // y_i += B x_j and y_j += B^T x_i. Pairs that cross chunks are read from both sides, so
  // chunks run on separate threads with no shared writes. The chunks depend only on the
  // pattern, so the sums, and the bits, are the same on any number of threads. Vectorised
  // (x and y padded to four per node; CPU clones): a non-finite value in a block may also
  // spoil the product of its block's other rows. Work buffers per thread, allocated once.
  void multiply_symmetric(const Vec& x, Vec& y) const;
  // Every block (i, j) equals the transpose of (j, i) to within relative_tolerance times the
  // largest entry (0: to the bit).
  bool is_symmetric(double relative_tolerance = 0.0) const;
  Index num_chunks() const { return static_cast<Index>(chunk_start_.size()) - 1; }
  // multiply_symmetric's row chunks (num_chunks() + 1 starts) and, per row, its in-chunk
  // blocks [chunk_lower(i), chunk_upper(i)).
  const std::vector<int>& chunk_start() const { return chunk_start_; }
  int chunk_lower(Index i) const { return chunk_lower_[i]; }
  int chunk_upper(Index i) const { return chunk_upper_[i]; }
  // Whether multiply_symmetric reads block k of row i: the diagonal, every block above it,
  // and the blocks below it whose column lies in an earlier row chunk. The others (below the
  // diagonal, inside the row's chunk) it takes as the transposes of their mirrors.
  bool is_product_block(Index i, int k) const { return k < chunk_lower_[i] || k >= diagonal_[i]; }
  // Those blocks of row i as two runs of block indices: [row start, chunk_lower(i)) and
  // [diagonal, row end).
  std::array<std::pair<int, int>, 2> product_runs(Index i) const {
    return {{{row_start_[i], chunk_lower_[i]}, {diagonal_[i], row_start_[i + 1]}}};
  }

  // Scalar CSR copy (symmetric, so it is also the CSC form) for direct solvers.
  // The pattern is built by the first call; later calls only copy values.
  void copy_to(Eigen::SparseMatrix<double, Eigen::ColMajor, int>& out) const;

 private:
  // multiply_symmetric on x and y stored four per node (x's fourth entries zero).
  void symmetric_kernel(const double* x4, double* y4) const;
  std::vector<int> row_start_;  // num_nodes + 1
  std::vector<int> columns_;    // block column of each block, sorted within a row
  std::vector<int> diagonal_;   // block index of (i, i)
  std::vector<double> values_;  // 9 per block, row-major inside the block
  // Row chunks of multiply_symmetric and, per row, where its in-chunk part begins and ends:
  // blocks [row_start_[i], chunk_lower_[i]) have columns before the row's chunk,
  // [chunk_upper_[i], row_start_[i + 1]) columns after it.
  std::vector<int> chunk_start_;
  std::vector<int> chunk_lower_, chunk_upper_;
};

}  // namespace corotate
