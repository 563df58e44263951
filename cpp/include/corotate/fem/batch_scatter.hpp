// Adding a batched kernel's stiffness blocks (ForceStiffnessBatch, element_kernel.hpp) to the
// global block-sparse values: for each element of the batch, each upper block (a, b) to its
// global block and its transpose to the mirrored one (b, a). A lane's nine entries lie
// 8 * Batch bytes apart.
#pragma once

#include <algorithm>
#include <type_traits>

#include "corotate/cpu_clones.hpp"
#include "corotate/fem/element_kernel.hpp"
#include "corotate/simd8.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

// dst += one lane's block (entry k = 3 r + c at K[k * Batch]), or its transpose. Straight
// from the lanes into the matrix, entry by entry: building the block in a local array first
// made the compiler store it as one wide vector and load it back in halves, a
// store-forwarding stall on every block (3 % of the sweep at 15,360 tets).
template <int Batch>
COROTATE_CLONE_INLINE void add_lane_block(double* dst, const double* K) {
  for (int k = 0; k < 9; ++k) dst[k] += K[k * Batch];
}
template <int Batch>
COROTATE_CLONE_INLINE void add_lane_block_transposed(double* dst, const double* K) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) dst[3 * c + r] += K[(3 * r + c) * Batch];
}

// ids: N * N global block indices per element, of count consecutive elements.
template <int N, int Batch>
COROTATE_CLONE_INLINE void add_batch_blocks(const ForceStiffnessBatch<N, Batch>& batch, int count, const int* ids,
                                            double* values) {
  for (int b = 0; b < count; ++b, ids += N * N) {
    int p = 0;
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j, ++p) {
        const double* K = &batch.K[p][0][b];
        add_lane_block<Batch>(values + 9 * ids[i * N + j], K);
        if (i != j) add_lane_block_transposed<Batch>(values + 9 * ids[j * N + i], K);  // diagonal ones are symmetric
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

// add_batch_blocks to the product blocks only (targets: one per element of the batch). Value
// double (from batch.K), or float for a SinglePrecisionSymmetric's values (from
// batch.K_single, the targets then in its stored blocks; summed in float32).
template <int N, int Batch, class Value>
COROTATE_CLONE_INLINE void add_batch_product_blocks(const ForceStiffnessBatch<N, Batch>& batch, int count,
                                                    const ProductBlockTargets<N>* targets, Value* values) {
  for (int b = 0; b < count; ++b) {
    const ProductBlockTargets<N>& t = targets[b];
    int p = 0, q = 0;
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j, ++p) {
        // entry k = 3 r + c at K[k * Batch]
        const Value* K = [&] {
          if constexpr (std::is_same_v<Value, float>) return &batch.K_single[p][0][b];
          else return &batch.K[p][0][b];
        }();
        if (i == j) {
          Value* d = values + 9 * t.diagonal[i];
          for (int k = 0; k < 9; ++k) d[k] += K[k * Batch];
          continue;
        }
        // Which of the block and its transpose goes above the diagonal depends on the node
        // numbers. A branch: a select of pointers or of entries kept the adds from
        // vectorising, and on the unstructured armadillo the branch costs no more. The
        // mirror below the diagonal is stored across row chunks only (lower >= 0). (Written
        // out: the same loops through add_lane_block compiled slower here, assembly 1.92 against
        // 2.19 ms at 15,360 tets, measured twice.)
        Value* up = values + 9 * t.upper[q];
        if (t.transposed[q]) {
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) up[3 * c + r] += K[(3 * r + c) * Batch];
          if (t.lower[q] >= 0) {
            Value* down = values + 9 * t.lower[q];
            for (int k = 0; k < 9; ++k) down[k] += K[k * Batch];
          }
        } else {
          for (int k = 0; k < 9; ++k) up[k] += K[k * Batch];
          if (t.lower[q] >= 0) {
            Value* down = values + 9 * t.lower[q];
            for (int r = 0; r < 3; ++r)
              for (int c = 0; c < 3; ++c) down[3 * c + r] += K[(3 * r + c) * Batch];
          }
        }
        ++q;
      }
  }
}

#if defined(COROTATE_HAVE_FLOAT8)
// add_batch_product_blocks into float32 values, eight lanes at a time through registers. The
// scalar loop above costs three instructions per entry (load the lane's entry, which lies
// 64 bytes from the next, add to the matrix's entry, store), 18 % of a step at 15,360 tets.
// Here the first eight entries of a block, taken from eight lanes, are turned from one
// vector per entry into one vector per element by an 8 x 8 transpose of shuffles (three
// per element and block), and each block is then one eight-wide add into the matrix plus
// its ninth entry.
#if !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // see simd8.hpp
#endif
namespace batch_scatter_detail {
using simd::add8;
using simd::Float8;
using simd::load8;

// rows[k][e] = entry k of element e -> out[e][k] (k, e < 8).
COROTATE_CLONE_INLINE void transpose8(const Float8 (&rows)[8], Float8 (&out)[8]) {
  Float8 t[8], u[8];
  for (int k = 0; k < 8; k += 2) {
    t[k] = __builtin_shufflevector(rows[k], rows[k + 1], 0, 8, 1, 9, 4, 12, 5, 13);
    t[k + 1] = __builtin_shufflevector(rows[k], rows[k + 1], 2, 10, 3, 11, 6, 14, 7, 15);
  }
  for (int k = 0; k < 8; k += 4)
    for (int h = 0; h < 2; ++h) {
      u[k + 2 * h] = __builtin_shufflevector(t[k + h], t[k + h + 2], 0, 1, 8, 9, 4, 5, 12, 13);
      u[k + 2 * h + 1] = __builtin_shufflevector(t[k + h], t[k + h + 2], 2, 3, 10, 11, 6, 7, 14, 15);
    }
  for (int e = 0; e < 4; ++e) {
    out[e] = __builtin_shufflevector(u[e], u[e + 4], 0, 1, 2, 3, 8, 9, 10, 11);
    out[e + 4] = __builtin_shufflevector(u[e], u[e + 4], 4, 5, 6, 7, 12, 13, 14, 15);
  }
}
// The first eight entries of a 3 x 3 block's transpose (the ninth, (2, 2), stays).
COROTATE_CLONE_INLINE Float8 transpose_block8(Float8 v) {
  return __builtin_shufflevector(v, v, 0, 3, 6, 1, 4, 7, 2, 5);
}
}  // namespace batch_scatter_detail

template <int N, int Batch>
COROTATE_CLONE_INLINE void add_batch_product_blocks_vectorised(const ForceStiffnessBatch<N, Batch>& batch, int count,
                                                               const ProductBlockTargets<N>* targets, float* values) {
  static_assert(Batch % 8 == 0, "lanes are transposed eight at a time");
  using namespace batch_scatter_detail;
  int p = 0, q = 0;
  for (int i = 0; i < N; ++i)
    for (int j = i; j < N; ++j, ++p) {
      const auto& K = batch.K_single[p];  // K[k][lane]
      for (int first = 0; first < count; first += 8) {
        Float8 rows[8], blocks[8];
        for (int k = 0; k < 8; ++k) rows[k] = load8(&K[k][first]);
        transpose8(rows, blocks);
        const int lanes = std::min(8, count - first);
        for (int e = 0; e < lanes; ++e) {
          const ProductBlockTargets<N>& t = targets[first + e];
          const float last = K[8][first + e];
          if (i == j) {
            float* d = values + 9 * t.diagonal[i];
            add8(d, blocks[e]);
            d[8] += last;
            continue;
          }
          // As in the scalar loop: which of the block and its transpose lies above the
          // diagonal depends on the node numbers; the mirror below it only across row chunks.
          float* up = values + 9 * t.upper[q];
          const Float8 turned = transpose_block8(blocks[e]);
          add8(up, t.transposed[q] ? turned : blocks[e]);
          up[8] += last;
          if (t.lower[q] >= 0) {
            float* down = values + 9 * t.lower[q];
            add8(down, t.transposed[q] ? blocks[e] : turned);
            down[8] += last;
          }
        }
      }
      if (i != j) ++q;
    }
}
#if !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#endif

// The tet batch's, compiled for AVX-512, AVX2 and the baseline (cpu_clones.hpp).
void add_batch_blocks(const ForceStiffnessBatch<4, 16>& batch, int count, const int* ids, double* values);
void add_batch_product_blocks(const ForceStiffnessBatch<4, 16>& batch, int count, const ProductBlockTargets<4>* targets,
                              double* values);
void add_batch_product_blocks(const ForceStiffnessBatch<4, 16>& batch, int count, const ProductBlockTargets<4>* targets,
                              float* values);

}  // namespace corotate
