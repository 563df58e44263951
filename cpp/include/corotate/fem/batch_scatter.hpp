// Adding a batched kernel's stiffness blocks (ForceStiffnessBatch, element_kernel.hpp) to the
// global block-sparse values: for each element of the batch, each upper block (a, b) to its
// global block and its transpose to the mirrored one (b, a). A lane's nine entries (8 * Batch
// bytes apart) are gathered into a contiguous block first, so that the adds into the matrix
// are Eigen's vector adds (two doubles at a time: Eigen picks its packets per translation
// unit, not per clone) instead of nine scalar read-modify-writes: 4 % off the sweep.
#pragma once

#include <algorithm>

#include "corotate/cpu_clones.hpp"
#include "corotate/fem/element_kernel.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

// ids: N * N global block indices per element, of count consecutive elements.
template <int N, int Batch>
COROTATE_CLONE_INLINE void add_batch_blocks(const ForceStiffnessBatch<N, Batch>& batch, int count, const int* ids,
                                            double* values) {
  using Block = Eigen::Matrix<double, 9, 1>;
  for (int b = 0; b < count; ++b, ids += N * N) {
    int p = 0;
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j, ++p) {
        Block block, transposed;
        for (int k = 0; k < 9; ++k) block[k] = batch.K[p][k][b];
        Eigen::Map<Block>(values + 9 * ids[i * N + j]) += block;
        if (i == j) continue;  // diagonal blocks are symmetric
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) transposed[3 * c + r] = block[3 * r + c];
        Eigen::Map<Block>(values + 9 * ids[j * N + i]) += transposed;
      }
  }
}

// Where an element's blocks go when only the blocks multiply_symmetric reads are assembled
// (Request::lower_blocks false; BlockSparseMatrix::is_product_block). Of the two blocks of a
// pair of nodes one is above the diagonal (always read) and its mirror below it is read
// only when the pair crosses row chunks: about a third fewer blocks to add per element.
template <int N>
struct ProductBlockTargets {
  static constexpr int num_pairs = N * (N - 1) / 2;
  int diagonal[N];
  int upper[num_pairs];        // global block above the diagonal of pair q (local a < b, in order)
  int lower[num_pairs];        // its mirror when multiply_symmetric reads it, else -1
  bool transposed[num_pairs];  // local (a, b) lies below the diagonal: upper gets K_ab^T
};

// The targets of one element from its N * N global block ids (ids[a * N + b]).
template <int N>
ProductBlockTargets<N> product_block_targets(const BlockSparseMatrix& pattern, const int* ids, const int* nodes) {
  ProductBlockTargets<N> t;
  int q = 0;
  for (int a = 0; a < N; ++a) {
    t.diagonal[a] = ids[a * N + a];
    for (int b = a + 1; b < N; ++b, ++q) {
      t.transposed[q] = nodes[a] > nodes[b];
      const int up = t.transposed[q] ? ids[b * N + a] : ids[a * N + b];
      const int down = t.transposed[q] ? ids[a * N + b] : ids[b * N + a];
      t.upper[q] = up;
      t.lower[q] = pattern.is_product_block(std::max(nodes[a], nodes[b]), down) ? down : -1;
    }
  }
  return t;
}

// add_batch_blocks to the product blocks only (targets: one per element of the batch).
template <int N, int Batch>
COROTATE_CLONE_INLINE void add_batch_product_blocks(const ForceStiffnessBatch<N, Batch>& batch, int count,
                                                    const ProductBlockTargets<N>* targets, double* values) {
  using Block = Eigen::Matrix<double, 9, 1>;
  for (int b = 0; b < count; ++b) {
    const ProductBlockTargets<N>& t = targets[b];
    int p = 0, q = 0;
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j, ++p) {
        Block block, transposed;
        for (int k = 0; k < 9; ++k) block[k] = batch.K[p][k][b];
        if (i == j) {
          Eigen::Map<Block>(values + 9 * t.diagonal[i]) += block;
          continue;
        }
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) transposed[3 * c + r] = block[3 * r + c];
        // Which of the two goes above the diagonal depends on the node numbers: a select of
        // pointers, not a branch (it would be mispredicted on an unstructured mesh).
        const Block* up = t.transposed[q] ? &transposed : &block;
        const Block* down = t.transposed[q] ? &block : &transposed;
        Eigen::Map<Block>(values + 9 * t.upper[q]) += *up;
        if (t.lower[q] >= 0) Eigen::Map<Block>(values + 9 * t.lower[q]) += *down;  // across chunks only
        ++q;
      }
  }
}

// The tet batch's, compiled for AVX-512, AVX2 and the baseline (cpu_clones.hpp).
void add_batch_blocks(const ForceStiffnessBatch<4, 16>& batch, int count, const int* ids, double* values);
void add_batch_product_blocks(const ForceStiffnessBatch<4, 16>& batch, int count, const ProductBlockTargets<4>* targets,
                              double* values);

}  // namespace corotate
