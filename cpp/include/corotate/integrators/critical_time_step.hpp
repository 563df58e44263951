// Stability limit of explicit integration: the highest eigenvalue of M^-1 A for a symmetric
// A (stiffness K or damping C) and a diagonal mass M, by Lanczos on M^-1/2 A M^-1/2.
//
// Symplectic Euler and velocity Verlet are both the leapfrog (central difference) scheme
// in disguise; on a mode x'' = -w^2 x - c x' either is stable when w^2 dt^2 + 2 c dt < 4,
//     dt_crit = (sqrt(c^2 + 4 w^2) - c) / w^2   (= 2 / w without damping),
// the usual (2 / w) (sqrt(1 + z^2) - z) with z = c / (2 w). For a whole system corotate
// takes w^2 = lambda_max(M^-1 K) and c = lambda_max(M^-1 C) + alpha (alpha: mass-
// proportional damping): every mode then satisfies the inequality, so the step is safe
// even though K and C do not share eigenvectors.
#pragma once

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

struct EigenEstimate {
  double ritz = 0;        // largest Ritz value (a lower bound of lambda_max)
  double residual = 0;    // |A y - ritz y| of its Ritz vector: an eigenvalue lies within this of ritz
  double value = 0;       // ritz + residual: the estimate used for time steps (errs on the safe side)
  int iterations = 0;
};

// Largest eigenvalue of M^-1 A on the DOFs with inv_sqrt_mass > 0 (fixed DOFs: 0).
// A: symmetric, 3n x 3n; inv_sqrt_mass: 3n entries 1 / sqrt(m). Stops when the residual
// falls below tolerance * ritz or after max_iterations matrix-vector products. Deterministic
// (fixed start vector). No reorthogonalisation: the extreme Ritz value does not need it.
EigenEstimate largest_eigenvalue(const BlockSparseMatrix& A, const Vec& inv_sqrt_mass, int max_iterations = 80,
                                 double tolerance = 1e-3);

// The formula above; omega_sq = w^2 [1/s^2], c [1/s]. Infinite when both are zero.
double critical_time_step(double omega_sq, double c);

}  // namespace corotate
