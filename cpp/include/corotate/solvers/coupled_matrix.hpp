// A + C in one sparse matrix, for a factor that knows the coupling (contact between two parts
// of a body, or a body and itself): the pattern of A joined with the node pairs C couples.
//
// CG multiplies with A + C without this (C stays an operator, linear_solver.hpp), but a
// factor of A alone leaves out the stiff springs between a node and the triangle it presses
// on, one outlying eigenvalue per contact, and CG then needs about as many iterations as
// there are contacts. So the factor-based solvers factorize this matrix instead, when a
// coupling is present; its pattern changes with the contacts, so each such factorization
// orders and analyses afresh.
#pragma once

#include "corotate/solvers/linear_solver.hpp"

namespace corotate {

// A (every block, lower ones included) plus C's blocks, on the union of their patterns.
BlockSparseMatrix with_coupling(const BlockSparseMatrix& A, const SystemCoupling& coupling);

}  // namespace corotate
