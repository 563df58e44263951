// Triangular solves with a supernodal Cholesky factor P A P^T = L L^T (CHOLMOD's layout),
// by our own sweeps over the supernodes with Eigen's dense kernels, on up to two threads.
// cholmod_solve does the same through BLAS (dtrsv, dgemv), which Debian's reference BLAS
// runs as unvectorised loops (15 % of a step at 122,880 tets), and allocates its result on
// every call.
//
// The sweeps are bound by the bytes of the factor they read (the two-level preconditioner's
// coarse factor at 122,880 tets is several MB, read twice per application), and one core
// does not reach the memory bandwidth that two do. Subtrees of the elimination tree that
// share no supernode are independent in both sweeps, so the tree is cut into a set of
// disjoint subtrees (the frontier), split into two bins of about equal work, and the
// supernodes above them (the top: each an ancestor of frontier subtrees). The supernodes
// come in postorder, so a subtree is a contiguous range ending at its root. Forward: the two
// bins side by side, each adding its updates of top rows to its own accumulator; then the
// accumulators in bin order, then the top in order. Backward: the top first, then the bins
// side by side (they only read the top). The split is the same on any number of threads,
// so the result is the same to the bit.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

// The arrays of a supernodal factor (CHOLMOD's names): n columns in nsuper supernodes,
// supernode s holding columns [super[s], super[s + 1]) and, from values + px[s], a column-
// major panel of pi[s + 1] - pi[s] rows whose row indices are rows[pi[s]...] (its own columns
// first). perm: L's row k is A's row perm[k].
struct SupernodalFactor {
  Index n = 0, nsuper = 0;
  const int* perm = nullptr;
  const int* super = nullptr;
  const int* pi = nullptr;
  const int* px = nullptr;
  const int* rows = nullptr;
};

// Where the supernodal tree splits for two threads (see above).
struct SupernodalSplit {
  std::vector<std::pair<Index, Index>> bins[2];  // each bin's subtrees, as supernode ranges
  std::vector<Index> top;                        // the supernodes above them, ascending
  std::vector<char> row_on_top;                  // per column of L: its supernode is on top
  Index max_below = 0;                           // the most rows a panel has below its columns
  static SupernodalSplit of(const SupernodalFactor& L);
};

// Work vectors of supernodal_solve, sized on first use.
template <typename Scalar>
struct SupernodalWork {
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  Vector y, gathered[2], top_updates[2];
};

// x = A^-1 b from the factor's values (float or double; sums in that precision).
template <typename Scalar>
void supernodal_solve(const SupernodalFactor& L, const SupernodalSplit& split, const Scalar* values, const Vec& b,
                      Vec& x, SupernodalWork<Scalar>& work);

}  // namespace corotate
