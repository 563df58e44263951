#include "corotate/solvers/two_level_preconditioner.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "corotate/parallel.hpp"
#include "corotate/solvers/linear_solver.hpp"  // SystemCoupling
#include "corotate/solvers/smoothed_aggregation.hpp"

namespace corotate {

namespace {

// DOFs that a FixedDofs projection decoupled: unit diagonal, nothing else in the row.
std::vector<char> decoupled_dofs(const BlockSparseMatrix& A) {
  std::vector<char> fixed(A.num_dofs(), 0);
  const auto& start = A.row_start();
  const auto& cols = A.columns();
  for (Index i = 0; i < A.num_nodes(); ++i)
    for (int r = 0; r < 3; ++r) {
      bool alone = true;
      for (int k = start[i]; k < start[i + 1] && alone; ++k)
        for (int c = 0; c < 3 && alone; ++c) {
          const double v = A.block(k)(r, c);
          alone = (cols[k] == i && c == r) ? v == 1.0 : v == 0.0;
        }
      fixed[3 * i + r] = alone;
    }
  return fixed;
}

}  // namespace

void TwoLevelPreconditioner::setup(const BlockSparseMatrix& A0) {
  const Index n = A0.num_nodes(), dofs = A0.num_dofs();
  if (rest_.cols() != n)
    throw InvalidInput("the two_level preconditioner needs the rest node positions (geometry) of the " +
                       std::to_string(n) + "-node system");
  // Built at the configuration of A0: its rigid-body modes are those of the positions A0 was
  // assembled at (the rest positions when none were given).
  const Nodes& built_at = positions_.cols() == n ? positions_ : rest_;
  rotations_.build(A0, built_at);  // the aggregates, each node's offset from their centre
  const Index m = rotations_.num_aggregates();
  const std::vector<int>& agg = rotations_.aggregate_of_node();
  const Nodes& offsets = rotations_.offsets();
  const std::vector<char> fixed = decoupled_dofs(A0);
  std::vector<std::vector<int>> members(m);
  for (Index i = 0; i < n; ++i) members[agg[i]].push_back(static_cast<int>(i));

  // Tentative prolongator: per aggregate, an orthonormal basis of its rigid-body modes
  // (translations e_k, rotations w x (X - c)), with fixed DOFs left out; one 3 x 6 block per
  // node (columns beyond the aggregate's rank zero).
  Block36List tentative(n, Block36::Zero());
  int coarse_dofs = 0;
  std::vector<int> coarse_start(1, 0);  // first coarse DOF of each aggregate
  for (int a = 0; a < m; ++a) {
    const auto& nodes = members[a];
    Eigen::MatrixXd modes = Eigen::MatrixXd::Zero(3 * nodes.size(), 6);
    for (size_t k = 0; k < nodes.size(); ++k) {
      const Vec3 d = offsets.col(nodes[k]);
      Mat3 rot;  // columns: displacement of this node for a unit rotation about x, y, z
      rot << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;
      modes.block<3, 3>(3 * k, 0).setIdentity();
      modes.block<3, 3>(3 * k, 3) = rot;
      for (int r = 0; r < 3; ++r)
        if (fixed[3 * nodes[k] + r]) modes.row(3 * k + r).setZero();
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(modes);
    qr.setThreshold(1e-10);
    const Index rank = qr.rank();
    if (rank > 0) {  // (a fully fixed aggregate has no coarse DOFs)
      const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(modes.rows(), rank);
      for (size_t k = 0; k < nodes.size(); ++k)
        for (int r = 0; r < 3; ++r)
          if (!fixed[3 * nodes[k] + r])
            for (Index c = 0; c < rank; ++c) tentative[nodes[k]](r, c) = Q(3 * k + r, c);
    }
    coarse_dofs += int(rank);
    coarse_start.push_back(coarse_dofs);
  }

  diagonal_.compute(A0);
  std::vector<Mat3> inverse_diagonal(n);
  for (Index i = 0; i < n; ++i) inverse_diagonal[i] = diagonal_.inverse_block(i);

  // lambda_max(D^-1 A0) by power iteration; 4 / (3 lambda) damps the highest modes.
  Vec x = Vec::Ones(dofs), y(dofs), w(dofs);
  double lambda = 1;
  for (int it = 0; it < 20; ++it) {
    A0.multiply(x, y);
    diagonal_.apply(y, w);
    lambda = w.norm() / x.norm();
    x = w / w.norm();
  }
  smoothing_weight_ = 4.0 / (3.0 * lambda);

  // The prolongator is smoothed a fifth harder than the textbook 4 / (3 lambda): fewer CG
  // iterations per step on the benchmark beams (100 steps: 6.71 -> 6.23 at 122,880 tets,
  // 5.31 -> 5.04 at 51,840, 4.13 -> 4.05 at 15,360, 6.86 -> 6.55 at dt = 0.04; Hex8 2.77 ->
  // 2.73), while 1.4 times was worse again (7.47 at 122,880 tets after 60 steps against 7.25).
  // The smoother keeps 4 / (3 lambda) (bench/README.md).
  const double prolongator_weight = 1.2 * smoothing_weight_;
  // P and P^T A P in blocks (smoothed_aggregation.hpp): the scalar sparse products of the
  // same matrices were most of the first step at 122,880 tets.
  const NodeAggregateBlocks P =
      smoothed_prolongator(A0, inverse_diagonal, agg, tentative, static_cast<int>(m), prolongator_weight);
  coarse_ = galerkin_product(A0, P, coarse_start);
  prolongator_ = BlockProlongator(P, coarse_start);
  coarse_start_ = coarse_start;
  // The contact terms' copy of the coarse matrix (same pattern) and their bookkeeping.
  coarse_with_terms_ = coarse_;
  coupled_pairs_.clear();
  for (auto& earlier : recent_terms_) earlier.clear();  // (of another hierarchy's nodes)
  coarse_positions_.clear();  // (the same pattern as coarse_)
  factored_with_terms_ = false;
  refactored_since_save_ = false;  // (a new hierarchy: no earlier factor to restore)
  excess_applies_ = 0;
  fewest_applies_ = std::numeric_limits<long>::max();
  node_mark_.assign(n, 0);
  // A refactorization's cost in applications: the coarse matrix is nearly dense (948
  // unknowns and 188,124 entries at 15,360 tets, whose factorization took 14-17 ms against
  // 0.47 ms per CG iteration), so it grows faster than an application; coarse unknowns / 30
  // is that measurement, and an underestimate on larger meshes (refactorizing more often).
  refactor_cost_in_applies_ = std::max<long>(10, coarse_dofs / 30);

  // The coarse solve reads the whole factor twice per application: a float copy halves
  // that (1e-7 relative changes to a preconditioner; same iterations, bench/README.md).
  coarse_factor_.set_single_precision_solve(true);
  coarse_factor_.analyze(coarse_);
  factorize_coarse(coarse_);
  turned_.resize(dofs);
  z4_.assign(4 * n, 0.0f);
  y4_.assign(4 * n, 0.0f);
  coarse_rhs_.resize(coarse_dofs);
  coarse_solution_.resize(coarse_dofs);
  ready_ = true;
}

void TwoLevelPreconditioner::factorize_coarse(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& coarse) {
  if (!coarse_factor_.factorize(coarse))
    throw NotPositiveDefinite("two-level preconditioner: the coarse matrix is not positive definite");
}

void TwoLevelPreconditioner::update_coarse_terms() {
  const bool any = terms_ && !terms_->empty();
  // The coupling between parts in contact (see the header): a new pair of aggregates grows
  // the coarse pattern, and the factor is made afresh.
  const bool coupled = coupling_ != nullptr;
  bool new_pairs = false;
  if (coupled) {
    coupled_aggregates(needed_pairs_);
    new_pairs =
        !std::includes(coupled_pairs_.begin(), coupled_pairs_.end(), needed_pairs_.begin(), needed_pairs_.end());
  }
  // Refactorize when the terms first appear (without them the coarse correction pushes
  // aggregates into the floor that holds them), and when the applications the factor cost
  // beyond the fewest one solve took since it was made (plus one: solves vary by one or two
  // as contacts come and go) add up to a refactorization's worth: a landing, a body lifted
  // off, a tool pushed somewhere else. Not at every change: contacts come and go from step to
  // step (the sides of the beam lying between two walls graze them and flip a third of its
  // aggregates every step), and a refactorization costs many steps' coarse solves.
  const bool contacts = any || coupled;
  const bool refactor = (contacts && !factored_with_terms_) || new_pairs ||
                        (factored_with_terms_ && excess_applies_ > refactor_cost_in_applies_);
  if (refactor) {
    if (!refactored_since_save_) {  // what a failed call restores
      saved_coarse_values_.assign(coarse_with_terms_.valuePtr(),
                                  coarse_with_terms_.valuePtr() + coarse_with_terms_.nonZeros());
      saved_pairs_ = coupled_pairs_;
      refactored_since_save_ = true;
    }
    if (new_pairs) {
      std::vector<std::pair<int, int>> merged;
      std::set_union(coupled_pairs_.begin(), coupled_pairs_.end(), needed_pairs_.begin(), needed_pairs_.end(),
                     std::back_inserter(merged));
      coupled_pairs_.swap(merged);
      extend_coarse_pattern();
    }
    add_terms_to_coarse(any);
    if (coupled) add_coupling();
    factorize_coarse(coarse_with_terms_);
    factored_with_terms_ = contacts;
    ++refactorizations_;
    excess_applies_ = 0;
    fewest_applies_ = std::numeric_limits<long>::max();
  }
  recent_latest_ = (recent_latest_ + 1) % static_cast<int>(recent_terms_.size());
  if (terms_) recent_terms_[recent_latest_] = *terms_;  // (reuses its storage)
  else recent_terms_[recent_latest_].clear();
  applies_ = 0;
}

void TwoLevelPreconditioner::save_state() {
  rotations_.save_state();
  saved_.recent_terms = recent_terms_;  // (reuses their storage)
  saved_.recent_latest = recent_latest_;
  saved_.factored_with_terms = factored_with_terms_;
  saved_.excess_applies = excess_applies_;
  saved_.fewest_applies = fewest_applies_;
  saved_.refactorizations = refactorizations_;
  refactored_since_save_ = false;
}

void TwoLevelPreconditioner::restore_state() {
  rotations_.restore_state();
  recent_terms_ = saved_.recent_terms;
  recent_latest_ = saved_.recent_latest;
  factored_with_terms_ = saved_.factored_with_terms;
  excess_applies_ = saved_.excess_applies;
  fewest_applies_ = saved_.fewest_applies;
  refactorizations_ = saved_.refactorizations;
  if (refactored_since_save_) {  // the factor of before the failed call, made again
    if (coupled_pairs_ != saved_pairs_) {  // (on the pattern of then)
      coupled_pairs_ = saved_pairs_;
      extend_coarse_pattern();
    }
    if (Index(saved_coarse_values_.size()) == coarse_with_terms_.nonZeros())
      std::copy(saved_coarse_values_.begin(), saved_coarse_values_.end(), coarse_with_terms_.valuePtr());
    factorize_coarse(coarse_with_terms_);
    refactored_since_save_ = false;
  }
}

void TwoLevelPreconditioner::solved(bool /*converged*/) {
  if (!factored_with_terms_) return;
  fewest_applies_ = std::min(fewest_applies_, applies_);
  excess_applies_ += std::max(0L, applies_ - fewest_applies_ - 1);
}

void TwoLevelPreconditioner::add_terms_to_coarse(bool any) {
  if (coarse_positions_.empty()) {  // the same pattern
    std::copy(coarse_.valuePtr(), coarse_.valuePtr() + coarse_.nonZeros(), coarse_with_terms_.valuePtr());
  } else {
    std::fill(coarse_with_terms_.valuePtr(), coarse_with_terms_.valuePtr() + coarse_with_terms_.nonZeros(), 0.0);
    for (Index k = 0; k < coarse_.nonZeros(); ++k)
      coarse_with_terms_.valuePtr()[coarse_positions_[k]] = coarse_.valuePtr()[k];
  }
  if (!any) return;
  add_terms(*terms_, nullptr);
  // The factor covers the recent solves' terms too, each node's latest (those of nodes not
  // in this one): a contact that flips on and off from step to step is then in it in both
  // phases, where it only makes the coarse level a little stiffer. On the beam between walls
  // (bench/contact_step.py) the contacts of the top edges graze the walls; with the last
  // solve's alone, which of them a factor held depended on the step it was made at: 2.6-4.0
  // CG iterations per step, 7-8 with this solve's alone; with those of the last three
  // solves, 2.3-2.5.
  std::fill(node_mark_.begin(), node_mark_.end(), 0);
  for (Index i : terms_->nodes) node_mark_[i] = 1;
  const int recent = static_cast<int>(recent_terms_.size());
  for (int back = 0; back < recent; ++back) {  // the latest first
    const DiagonalTerms& earlier = recent_terms_[(recent_latest_ - back + recent) % recent];
    add_terms(earlier, &node_mark_);
    for (Index i : earlier.nodes) node_mark_[i] = 1;
  }
}

void TwoLevelPreconditioner::add_terms(const DiagonalTerms& terms, const std::vector<char>* skip) {
  // The factor is rare, so it takes the terms through the smoothed P (Galerkin, exact):
  // P_i^T R^T H_i R P_i for node i's row of (aggregate) blocks, R the rotation of node i's
  // aggregate (the coarse correction works in that frame, apply()).
  const std::vector<int>& aggregate = rotations_.aggregate_of_node();
  const bool rotated = rotations_.rotated();
  for (size_t t = 0; t < terms.nodes.size(); ++t) {
    const Index i = terms.nodes[t];
    if (skip && (*skip)[i]) continue;
    const Mat3& rotation = rotations_.rotation(aggregate[i]);
    const Mat3 h = rotated ? Mat3(rotation.transpose() * terms.blocks[t] * rotation) : terms.blocks[t];
    // (Aggregates a and b share node i, so P^T A P has their whole block.)
    for (int k1 = prolongator_.node_begin(i); k1 < prolongator_.node_end(i); ++k1) {
      const Eigen::Matrix<double, 6, 3> left = prolongator_.block(k1).transpose() * h;
      for (int k2 = prolongator_.node_begin(i); k2 < prolongator_.node_end(i); ++k2)
        add_coarse_block(prolongator_.block_aggregate(k1), prolongator_.block_aggregate(k2),
                         left * prolongator_.block(k2));
    }
  }
}

void TwoLevelPreconditioner::add_coarse_block(int a, int b, const Eigen::Matrix<double, 6, 6>& product) {
  const int* outer = coarse_with_terms_.outerIndexPtr();
  const int* inner = coarse_with_terms_.innerIndexPtr();
  double* values = coarse_with_terms_.valuePtr();
  const int first_a = coarse_start_[a], rank_a = coarse_start_[a + 1] - first_a, first_b = coarse_start_[b];
  for (int c = 0; c < coarse_start_[b + 1] - first_b; ++c) {
    const int col = first_b + c;  // (a's coarse DOFs are consecutive rows of the column)
    const int* row = std::lower_bound(inner + outer[col], inner + outer[col + 1], first_a);
    for (int r = 0; r < rank_a; ++r, ++row) {
      if (row == inner + outer[col + 1] || *row != first_a + r)
        throw InvalidInput("two-level preconditioner: a contact term outside the coarse pattern");
      values[row - inner] += product(r, c);
    }
  }
}

void TwoLevelPreconditioner::coupled_aggregates(std::vector<std::pair<int, int>>& pairs) const {
  pairs.clear();
  coupling_->for_each_block([&](Index i, Index j, const Mat3&) {
    for (int k1 = prolongator_.node_begin(i); k1 < prolongator_.node_end(i); ++k1)
      for (int k2 = prolongator_.node_begin(j); k2 < prolongator_.node_end(j); ++k2)
        pairs.emplace_back(prolongator_.block_aggregate(k1), prolongator_.block_aggregate(k2));
  });
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

void TwoLevelPreconditioner::add_coupling() {
  // P(x)^T C P(x), block by block: P_i^T R_a(i)^T B R_a(j) P_j for C's block B at nodes (i, j),
  // each node in its own aggregate's turned frame (apply()).
  const std::vector<int>& aggregate = rotations_.aggregate_of_node();
  const bool rotated = rotations_.rotated();
  coupling_->for_each_block([&](Index i, Index j, const Mat3& block) {
    const Mat3 b = rotated
                       ? Mat3(rotations_.rotation(aggregate[i]).transpose() * block * rotations_.rotation(aggregate[j]))
                       : block;
    for (int k1 = prolongator_.node_begin(i); k1 < prolongator_.node_end(i); ++k1) {
      const Eigen::Matrix<double, 6, 3> left = prolongator_.block(k1).transpose() * b;
      for (int k2 = prolongator_.node_begin(j); k2 < prolongator_.node_end(j); ++k2)
        add_coarse_block(prolongator_.block_aggregate(k1), prolongator_.block_aggregate(k2),
                         left * prolongator_.block(k2));
    }
  });
}

void TwoLevelPreconditioner::extend_coarse_pattern() {
  // coarse_'s entries and every coupled pair's block, then where coarse_'s entries sit.
  const int n = static_cast<int>(coarse_.cols());
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(static_cast<size_t>(coarse_.nonZeros()) + 36 * coupled_pairs_.size());
  for (int col = 0; col < n; ++col)
    for (Eigen::SparseMatrix<double, Eigen::ColMajor, int>::InnerIterator it(coarse_, col); it; ++it)
      entries.emplace_back(it.row(), col, 0.0);
  for (const auto& [a, b] : coupled_pairs_)
    for (int col = coarse_start_[b]; col < coarse_start_[b + 1]; ++col)
      for (int row = coarse_start_[a]; row < coarse_start_[a + 1]; ++row) entries.emplace_back(row, col, 0.0);
  coarse_with_terms_.resize(n, n);
  coarse_with_terms_.setFromTriplets(entries.begin(), entries.end());
  coarse_with_terms_.makeCompressed();
  coarse_positions_.resize(static_cast<size_t>(coarse_.nonZeros()));
  const int* outer = coarse_with_terms_.outerIndexPtr();
  const int* inner = coarse_with_terms_.innerIndexPtr();
  for (int col = 0; col < n; ++col)
    for (int k = coarse_.outerIndexPtr()[col]; k < coarse_.outerIndexPtr()[col + 1]; ++k)
      coarse_positions_[k] = static_cast<int>(
          std::lower_bound(inner + outer[col], inner + outer[col + 1], coarse_.innerIndexPtr()[k]) - inner);
  coarse_factor_.analyze(coarse_with_terms_);
}

void TwoLevelPreconditioner::set_positions(const Nodes& x) {
  positions_ = x;  // no allocation once sized
  positions_pending_ = true;
}

void TwoLevelPreconditioner::turn(Index num_nodes) {
  if (positions_.cols() != 0 && positions_.cols() != num_nodes)
    throw InvalidInput("two_level preconditioner: positions of " + std::to_string(positions_.cols()) + " nodes for a " +
                       std::to_string(num_nodes) + "-node system");
  if (ready_ && positions_pending_) rotations_.update(positions_);
  positions_pending_ = false;
}

void TwoLevelPreconditioner::compute(const BlockSparseMatrix& A) {
  turn(A.num_nodes());  // before the build, only checks the positions (the build starts there)
  if (!ready_) {
    if (terms_ && !terms_->empty()) {  // the hierarchy of the body's own system
      // (not in the fixed DOFs' identity rows, which the build recognises as fixed)
      const std::vector<char> fixed = decoupled_dofs(A);
      BlockSparseMatrix own = A;
      for (size_t k = 0; k < terms_->nodes.size(); ++k) {
        const Index i = terms_->nodes[k];
        auto block = own.block(own.diagonal_block(i));
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            if (!fixed[3 * i + r] && !fixed[3 * i + c]) block(r, c) -= terms_->blocks[k](r, c);
      }
      setup(own);
    } else {
      setup(A);
    }
  }
  update_coarse_terms();
  A_single_.assign(A);
  diagonal_.compute(A);
}

void TwoLevelPreconditioner::compute_assembled() {
  if (!ready_) throw InvalidInput("two_level preconditioner: a float32 system before the hierarchy was built");
  turn(A_single_.num_nodes());
  update_coarse_terms();
  // A matrix the step kept (kept_system.hpp) has the smoother it had.
  if (A_single_.assembly_count() != diagonal_assembly_) diagonal_.compute(A_single_);
  diagonal_assembly_ = A_single_.assembly_count();
}

void TwoLevelPreconditioner::apply(const Vec& r, Vec& z) {
  // Symmetric V(1,1): smooth, coarse-correct (with P(x) = R(x) P), smooth. Every pass over
  // the fine vectors is fused with its neighbours, node by node: the two products read and
  // write the four-per-node vectors directly, the residual r - A z is formed as the product
  // is read back, and turned into the aggregates' build frame in the same loop.
  ++applies_;
  const Index n = A_single_.num_nodes();
  const bool rotated = rotations_.rotated();
  const std::vector<int>& aggregate = rotations_.aggregate_of_node();
  const double w = smoothing_weight_, unscale = A_single_.unscale();
  z.resize(3 * n);
  float* z4 = z4_.data();
  const float* y4 = y4_.data();
  // Node i's residual r - (A + C) z from the last product (C: the coupling between parts in
  // contact, when there is one; its product is over the contacts alone), and z_i written to
  // both layouts.
  const bool coupled = coupling_ != nullptr;
  auto couple = [&] {
    if (!coupled) return;
    coupled_product_.setZero(3 * n);
    coupling_->multiply_add(z, coupled_product_);
  };
  auto residual = [&](Index i) {
    Vec3 res(r[3 * i] - unscale * y4[4 * i], r[3 * i + 1] - unscale * y4[4 * i + 1],
             r[3 * i + 2] - unscale * y4[4 * i + 2]);
    if (coupled) res -= coupled_product_.segment<3>(3 * i);
    return res;
  };
  auto set_z = [&](Index i, const Vec3& zi) {
    z.segment<3>(3 * i) = zi;
    z4[4 * i] = float(zi[0]), z4[4 * i + 1] = float(zi[1]), z4[4 * i + 2] = float(zi[2]);
  };
  // z = w D^-1 r.
  COROTATE_PARALLEL_FOR(n >= 512)
  for (Index i = 0; i < n; ++i) set_z(i, w * (diagonal_.inverse_block(i) * r.segment<3>(3 * i)));
  A_single_.multiply_padded(z4, y4_.data());
  couple();
  // Coarse right-hand side P(x)^T (r - A z).
  COROTATE_PARALLEL_FOR(n >= 512)
  for (Index i = 0; i < n; ++i) {
    const Vec3 res = residual(i);
    turned_.segment<3>(3 * i).noalias() = rotated ? Vec3(rotations_.rotation(aggregate[i]).transpose() * res) : res;
  }
  prolongator_.restrict_to(turned_, coarse_rhs_);
  coarse_factor_.solve(coarse_rhs_, coarse_solution_);
  prolongator_.prolong(coarse_solution_, turned_, false);
  // z += P(x) e.
  COROTATE_PARALLEL_FOR(n >= 512)
  for (Index i = 0; i < n; ++i) {
    const Vec3 e = turned_.segment<3>(3 * i);
    set_z(i, z.segment<3>(3 * i) + (rotated ? Vec3(rotations_.rotation(aggregate[i]) * e) : e));
  }
  A_single_.multiply_padded(z4, y4_.data());
  couple();
  // z += w D^-1 (r - A z).
  COROTATE_PARALLEL_FOR(n >= 512)
  for (Index i = 0; i < n; ++i) z.segment<3>(3 * i) += w * (diagonal_.inverse_block(i) * residual(i));
}

}  // namespace corotate
