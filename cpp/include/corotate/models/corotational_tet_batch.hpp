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

// The inputs of one batch, packed by the kernel: G = dN/dX, R the element rotation, y the
// positions the force is evaluated at (the linearisation's y, or x).
struct TetBatchInput {
  alignas(64) double G[4][3][kTetBatch];  // G[a][k][b] = dN_a/dX_k of element b
  alignas(64) double R[3][3][kTetBatch];  // R[i][j][b]
  alignas(64) double y[4][3][kTetBatch];  // y[a][i][b]: node a's position
  alignas(64) double F[3][3][kTetBatch];  // deformation gradient where R was extracted
  alignas(64) double volume[kTetBatch];
};

// Fills out's forces f_a = -V R sigma(sym(R^T y G) - I) G_a, the upper stiffness blocks
// scale V (lambda a_i a_j^T + mu a_j a_i^T + mu (a_i . a_j) I), a = R G^T, the energy
// V/2 strain : sigma(strain) with strain = sym(R^T F) - I, and det F, of all kTetBatch lanes.
void corotational_tet_batch(const TetBatchInput& in, double lambda, double mu, double scale,
                            ForceStiffnessBatch<4, kTetBatch>& out);

}  // namespace corotate
