// The dense kernels of the supernodal Cholesky factorization (supernodal_numeric.cpp), on
// column-major panels. They hold nearly all of a large factorization's floating-point work,
// so they are compiled once per instruction-set level (cpu_clones.hpp) with register-blocked
// inner loops of eight-double vectors: Eigen's own dense products in the rest of the library
// are compiled for the x86-64 baseline (two doubles per instruction).
#pragma once

namespace corotate {

// In place: the m x k panel P (leading dimension m) becomes [L11; L21] with L11 L11^T the
// top k x k block (lower triangle read and written; the strict upper triangle is left as it
// is) and L21 = P21 L11^-T. False when the block is not positive definite (or not finite).
bool factor_panel(double* panel, int m, int k);

// U -= B B^T on the lower triangle of the b x b matrix U (leading dimension b), B the b x k
// block at `B` with leading dimension ldb.
void subtract_lower_product(const double* B, int ldb, int b, int k, double* U);

}  // namespace corotate
