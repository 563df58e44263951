// Dense kernels compiled once per instruction-set level (cpu_clones.hpp): Eigen's own dense
// products in the rest of the library are compiled for the x86-64 baseline (two doubles per
// instruction). Those of the supernodal Cholesky factorization (supernodal_numeric.cpp), on
// column-major panels, hold nearly all of a large factorization's floating-point work
// (register-blocked inner loops of eight-double vectors); the small LU's serve the floating
// frame's step.
#pragma once

namespace corotate {

// In place: the m x k panel P (leading dimension m) becomes [L11; L21] with L11 L11^T the
// top k x k block (lower triangle read and written; the strict upper triangle is left as it
// is) and L21 = P21 L11^-T. False when the block is not positive definite (or not finite).
bool factor_panel(double* panel, int m, int k);

// In place: the n x n column-major A becomes L (unit, strictly below the diagonal) and U with
// P A = L U, swaps[k] the row swapped with row k at step k (partial pivoting). False when a
// pivot is zero or not finite.
bool factor_lu(double* a, int n, int* swaps);
// x = A^-1 x from factor_lu's result.
void solve_lu(const double* lu, int n, const int* swaps, double* x);

// U -= B B^T on the lower triangle of the b x b matrix U (leading dimension b), B the b x k
// block at `B` with leading dimension ldb.
void subtract_lower_product(const double* B, int ldb, int b, int k, double* U);

}  // namespace corotate
