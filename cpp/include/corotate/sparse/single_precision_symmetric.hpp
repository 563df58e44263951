// A float32 copy of a symmetric block-sparse matrix for products inside a preconditioner.
//
// A product with the system matrix reads every stored value once, and at 15,360 tets those
// values (the upper blocks that BlockSparseMatrix::multiply_symmetric reads) are 2 MB of
// doubles: the product is bound by the bytes it moves. The two-level preconditioner makes
// two such products per application, and a preconditioner only has to be a fixed symmetric
// positive definite operator, not the exact matrix, so these products may use the values
// rounded to float32 (relative error 6e-8), and so may the vectors and the sums: half the
// bytes, and at that size the copy fits one core's L2 cache. At loose tolerances CG multiplies with
// the same copy (pcg.hpp, kSinglePrecisionProductTolerance): the system it then solves is A
// to 6e-8 per entry, far inside the residual it is asked for; tighter solves stay in double.
//
// The copy stores, row by row, exactly the blocks multiply_symmetric reads (those across
// row chunks on both sides, the diagonal, the upper ones inside the chunk) in the order it
// reads them, so the product streams through one array. Values are scaled by a power of two
// that brings the largest to about one, so float32's range never overflows or flushes a
// matrix whose entries are all huge or all tiny; the scaling is exact.
#pragma once

#include <cstdint>
#include <vector>

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class SinglePrecisionSymmetric {
 public:
  // Copies A's values; builds the layout on the first call and whenever A's pattern differs
  // from the one it was built for. A must be exactly symmetric (as for multiply_symmetric).
  void assign(const BlockSparseMatrix& A);
  // y = A x with A the copy assigned last (x, y: num_dofs(); no allocation once sized).
  // Same row chunks as multiply_symmetric: the same bits on any thread count.
  void multiply(const Vec& x, Vec& y) const;
  // The product on vectors stored four entries per node (x4's fourth entries zero), without
  // the copies in and out: y4 = A x4 / unscale() (a caller fusing its own passes with the
  // product scales as it reads y4). x4 and y4 in float32 like the values: the sums are too
  // (relative 1e-7 of a row's sum of |a||x|; 30 % fewer instructions than widening each
  // value to double, and half the vectors' bytes).
  void multiply_padded(const float* x4, float* y4) const { kernel(x4, y4); }
  double unscale() const { return unscale_; }
  Index num_nodes() const { return static_cast<Index>(row_first_.size()) - 1; }
  Index num_blocks() const { return static_cast<Index>(columns_.size()); }

  // --- Assembling straight into the copy ---
  // The implicit step may assemble its next system here instead of in a double matrix that
  // is then copied (LinearSolver::single_precision_target): the mass copy, the double
  // scatter and the conversion pass are a tenth of a step. The copy keeps the layout and
  // the power-of-two scale of its last assign(); entries are accumulated in float32 (a few
  // roundings of 6e-8 per entry, still far below the loose tolerances this path is for).
  bool has_layout() const { return pattern_blocks_ >= 0; }
  // Identifies the layout (changes whenever it is rebuilt, and differs between objects):
  // callers that keep block positions (block_position) recompute them when it changes.
  std::uint64_t layout_id() const { return layout_id_; }
  // The stored block that holds block k of the matrix the layout was built from (same
  // pattern), or -1 where the product does not read it (is_product_block false).
  int block_position(int k) const { return block_position_[k]; }
  Index num_pattern_blocks() const { return static_cast<Index>(block_position_.size()); }
  // The values, 9 per stored block (row-major), each the true value divided by unscale().
  float* values() { return values_.data(); }
  // Counts assign() and start_assembly() calls: a reader that computed something from the
  // values under one count (a smoother's inverted diagonal) may keep it while the count is
  // the same (the writes through values() belong to the assembly that began).
  std::uint64_t assembly_count() const { return assemblies_; }
  // A copy of the values, and back (the body's part of a system the step keeps while its
  // contacts change); restoring counts as an assembly. Throws InvalidInput for a copy of
  // another size.
  void save_values(std::vector<float>& to) const { to.assign(values_.begin(), values_.end()); }
  void restore_values(const std::vector<float>& from);
  // Begins an assembly: the values become s M (M in the pattern of the layout, e.g. the
  // mass matrix). The float image of s M is kept and made again only when s, the scale or
  // the caller's version number of M change, so a step starts with a copy of 4 bytes per
  // value. Throws InvalidInput when M's pattern is not the layout's.
  void start_assembly(const BlockSparseMatrix& M, double s, std::uint64_t version);
  // Adds value * I to node i's diagonal block.
  void add_to_diagonal(Index i, double value);
  // Adds a symmetric 3 x 3 block to node i's diagonal block.
  void add_to_diagonal_block(Index i, const Mat3& value);
  // Node i's diagonal block in true units (double).
  Mat3 diagonal_block(Index i) const;
  // Its nine stored values (divided by unscale(), row-major).
  const float* diagonal_block_values(Index i) const { return values_.data() + 9 * diagonal_[i]; }

 private:
  void build_layout(const BlockSparseMatrix& A);
  void kernel(const float* x4, float* y4) const;
  // Converts A's product blocks, times scale, into out in the stored order.
  void convert_from(const BlockSparseMatrix& A, double scale, float* out) const;

  // The pattern the layout was built for (a different matrix of the same pattern reuses it).
  std::vector<int> pattern_rows_;
  const int* pattern_columns_ = nullptr;
  Index pattern_blocks_ = -1;
  std::vector<int> chunk_start_;  // A's row chunks
  // Per row i, its stored blocks are [row_first_[i], row_first_[i + 1]): first those whose
  // column lies before the row's chunk, then the diagonal at diagonal_[i], then the upper
  // ones inside the chunk up to chunk_end_[i], then those after the chunk.
  std::vector<int> row_first_, diagonal_, chunk_end_;
  std::vector<int> columns_;  // column of each stored block
  std::vector<float> values_;  // 9 per stored block, row-major, scaled; 4 floats of padding
  double unscale_ = 1.0;       // the power of two the values were divided by
  std::vector<int> block_position_;  // per block of the pattern: its stored block, or -1
  std::uint64_t layout_id_ = 0;
  std::uint64_t assemblies_ = 0;
  // start_assembly's image of s M and what it was made from.
  std::vector<float> start_values_;
  double start_s_ = 0.0, start_unscale_ = 0.0;
  std::uint64_t start_version_ = 0, start_layout_ = 0;
};

}  // namespace corotate
