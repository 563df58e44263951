// The co-rotational tet kernel's forces and stiffness blocks for a batch of elements at once,
// in structure-of-arrays form (lane b = element b of the batch): the loops run over the
// lanes, which the compiler vectorises (and COROTATE_CPU_CLONES compiles for AVX-512 and
// AVX2), where one element at a time is a few hundred scalar multiply-adds on 3x3 matrices.
// Same formulas as CorotationalKernel<Tet4>::forces and ::stiffness
// (corotational_tet_kernel.hpp).
#pragma once

#include "corotate/fem/element_kernel.hpp"

namespace corotate {

constexpr int kTetBatch = 16;

// The constants of one batch, packed once when the model is built (so that the sweep reads
// them as they are, instead of transposing them from the elements every step): G = dN/dX,
// the volume and the Lame parameters of the element's material, lane b for element b (lanes
// past the batch's count repeat its first).
struct TetBatchElements {
  alignas(64) double G[4][3][kTetBatch];  // G[a][k][b] = dN_a/dX_k of element b
  alignas(64) double volume[kTetBatch];
  alignas(64) double lambda[kTetBatch];
  alignas(64) double mu[kTetBatch];
};

// The inputs of one batch: its constants, R the element rotation, y the positions the force
// is evaluated at (the linearisation's y, or x), F the deformation gradient at x.
struct TetBatchInput {
  const TetBatchElements* elements = nullptr;
  alignas(64) double R[3][3][kTetBatch];  // R[i][j][b]
  alignas(64) double y[4][3][kTetBatch];  // y[a][i][b]: node a's position
  alignas(64) double F[3][3][kTetBatch];  // deformation gradient where R was extracted
};

// Fills in's y from the positions `at` and F = x G from x (3 x n column-major arrays),
// nodes: 4 per element of the batch's count (lanes past count repeat the first element).
void gather_tet_batch(const TetBatchElements& elements, const double* x, const double* at, const int* nodes, int count,
                      TetBatchInput& in);

// Fills out's forces f_a = -V R sigma(sym(R^T y G) - I) G_a, the upper stiffness blocks
// scale V (lambda a_i a_j^T + mu a_j a_i^T + mu (a_i . a_j) I), a = R G^T, the energy
// V/2 strain : sigma(strain) with strain = sym(R^T F) - I, and det F, of all kTetBatch lanes
// (lambda, mu: each lane's own, from in.elements).
void corotational_tet_batch(const TetBatchInput& in, double scale, ForceStiffnessBatch<4, kTetBatch>& out);

}  // namespace corotate
