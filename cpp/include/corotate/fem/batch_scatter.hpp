// Adding a batched kernel's stiffness blocks (ForceStiffnessBatch, element_kernel.hpp) to the
// global block-sparse values: for each element of the batch, each upper block (a, b) to its
// global block and its transpose to the mirrored one (b, a). A lane's nine entries (8 * Batch
// bytes apart) are gathered into a contiguous block first, so that the adds into the matrix
// are Eigen's vector adds (two doubles at a time: Eigen picks its packets per translation
// unit, not per clone) instead of nine scalar read-modify-writes: 4 % off the sweep.
#pragma once

#include "corotate/cpu_clones.hpp"
#include "corotate/fem/element_kernel.hpp"

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

// The tet batch's, compiled for AVX-512, AVX2 and the baseline (cpu_clones.hpp).
void add_batch_blocks(const ForceStiffnessBatch<4, 16>& batch, int count, const int* ids, double* values);

}  // namespace corotate
