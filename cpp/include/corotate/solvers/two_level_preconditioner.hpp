// Two-level (smoothed-aggregation) preconditioner for meshes too large to factorize.
//
// Nodes are grouped into aggregates of a node and its neighbours. Each aggregate's coarse
// space is its six rigid-body modes (three translations, three infinitesimal rotations), the
// near-kernel of elasticity that a point smoother cannot reduce. The tentative prolongator
// is smoothed once by damped Jacobi, P = (I - w D^-1 A0) P_tent, and the coarse matrix
// Pc = P^T A0 P of the first system it sees (the rest state) is factorized once. Each
// application is a symmetric V(1,1) cycle: damped block-Jacobi smoothing with the current
// matrix (its residual products from a float32 copy), coarse correction with the fixed
// factor, smoothing again. Setup costs a few
// sparse products instead of a fine-level factorization whose fill grows as n^(4/3) or
// worse; an application costs three matrix-vector products' worth of work.
//
// Following the body's rotation. A frozen coarse level is right only near the configuration
// it was built at: when the body turns, the rigid-body modes of the current system are the
// turned ones, and P^T A P of the turned system is no longer the factorized coarse matrix
// (the coarse correction then over- or under-corrects; on the armadillo hanging from a
// point and swinging, CG to 1e-4 took 23 iterations at the start and 159 after 40 steps).
// Given the positions each system is assembled at (set_positions), each aggregate's
// rotation from the build configuration is found by shape matching (the polar rotation of
// sum_i x_i (X_i - c)^T over its nodes) and the coarse correction is applied in the
// aggregate's turned frame: P(x) = R(x) P, with R(x) the block diagonal of each node's
// aggregate rotation. For a rigid rotation R of the whole body, A = R A0 R^T (the mass is
// isotropic), so P(x)^T A P(x) = P^T A0 P: the frozen factor stays exact and the coarse
// space is the current near-kernel. Cost per application: two rotations of a fine vector.
//
// Contact. A contact spring (k n n^T, k a hundred times the node's own stiffness, and
// friction's tangential damping) is in the fine matrix but not in the frozen coarse one, and
// the coarse correction then pushes whole aggregates into the floor that holds them: the
// 15,360-tet beam lying between two walls (1,062 contacts) took 20 capped iterations that
// left 10-45 % of the residual, and 110-140 at every impact. So the step's diagonal terms
// (diagonal_terms.hpp) go into the coarse matrix, P(x)^T A0 P(x) + P(x)^T C P(x), through
// the smoothed prolongator; the coarse matrix is refactorized (same pattern) only when
// that pays (update_coarse_terms), since it is nearly dense. The hierarchy itself is built
// without the first system's terms.
//
// Contact between parts. A node pressed on another part's triangle is a stiff spring between
// the node and the triangle's corners: diagonal terms, which the coarse matrix takes as above,
// and a coupling C between nodes that share no element (linear_solver.hpp SystemCoupling).
// With the diagonal terms alone the coarse level held both parts to the ground where they
// touch: two 6,000-tet cubes stacked on the floor took 193 CG iterations per step at rest
// (bench/contact_step.py; 42 with the two changes below). So the coupling goes into the
// coarse matrix too, P(x)^T C P(x):
// blocks between aggregates of different parts, which P^T A0 P does not have. The coarse
// pattern grows by the aggregate pairs the coupling needs (analysed afresh when a new pair
// appears; kept, grown only, while the contacts come and go), and the coarse matrix is
// refactorized as for the diagonal terms. And the cycle's residuals take the coupling's
// product, r - (A + C) z: without it the smoothing passes treated the parts as apart.
#pragma once

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "corotate/solvers/aggregate_rotations.hpp"
#include "corotate/solvers/block_prolongator.hpp"
#include "corotate/solvers/preconditioner.hpp"
#include "corotate/solvers/sparse_cholesky.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate {

class TwoLevelPreconditioner final : public Preconditioner {
 public:
  void reset() override { ready_ = false; }
  // Rest positions (3 x n): the rotation modes of each aggregate are built from them.
  void set_geometry(const Nodes& rest) override {
    rest_ = rest;
    ready_ = false;
  }
  // Positions (3 x n) the next system is assembled at. The hierarchy is built at the first
  // ones it gets (the rest positions when it gets none); later ones turn its coarse level.
  void set_positions(const Nodes& x) override;
  void set_diagonal_terms(const DiagonalTerms* terms) override { terms_ = terms; }
  void set_coupling(const SystemCoupling* coupling) override { coupling_ = coupling; }
  void solved(bool converged) override;
  void compute(const BlockSparseMatrix& A) override;
  void apply(const Vec& r, Vec& z) override;
  double default_tolerance() const override { return 2e-2; }
  // Only to build the hierarchy (P^T A0 P reads all of A0); the cycle's products, the
  // block diagonal and the float32 copy read the product blocks.
  bool needs_lower_blocks() const override { return !ready_; }
  const SinglePrecisionSymmetric* single_precision_matrix() const override { return &A_single_; }
  // Once built (the first system comes in double: the hierarchy reads all of it), later
  // systems may be assembled straight into the float32 copy.
  SinglePrecisionSymmetric* assembly_target() override { return ready_ ? &A_single_ : nullptr; }
  void compute_assembled() override;
  Index coarse_size() const { return coarse_.rows(); }
  // How many times the coarse matrix was refactorized for the diagonal terms.
  int coarse_refactorizations() const { return refactorizations_; }
  // Each aggregate's rotation from the configuration the hierarchy was built at (identities
  // until positions arrive after the build).
  const AggregateRotations& rotations() const { return rotations_; }
  // The hierarchy is built once; only the aggregates' rotations change from step to step,
  // and the contact terms' factor (restored, and refactorized, only if the failed call
  // refactorized it).
  void save_state() override;
  void restore_state() override;

 private:
  void setup(const BlockSparseMatrix& A0);
  void turn(Index num_nodes);  // the coarse level to the pending positions
  // The coarse factor to the current diagonal terms (refactorized when they changed enough).
  void update_coarse_terms();
  void factorize_coarse(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& coarse);
  // coarse_with_terms_ = coarse_ + the terms of this solve and of the kRecentSolves - 1
  // before it, each node's latest (any: there are terms now).
  void add_terms_to_coarse(bool any);
  // coarse_with_terms_ += the terms through P, Galerkin (skip: nodes to leave out).
  void add_terms(const DiagonalTerms& terms, const std::vector<char>* skip);
  // coarse_with_terms_ += P(x)^T C P(x) of the coupling.
  void add_coupling();
  // coarse_with_terms_ += the 6 x 6 block `product` at aggregates (a, b) (in its pattern).
  void add_coarse_block(int a, int b, const Eigen::Matrix<double, 6, 6>& product);
  // The aggregate pairs the coupling's blocks join (sorted, both orders) into pairs.
  void coupled_aggregates(std::vector<std::pair<int, int>>& pairs) const;
  // coarse_with_terms_'s pattern: coarse_'s and every pair's blocks; analysed for the factor.
  void extend_coarse_pattern();

  Nodes rest_;
  Nodes positions_;             // the latest set_positions (empty: none given)
  bool positions_pending_ = false;  // set_positions since the last compute
  AggregateRotations rotations_;  // the aggregates and their turn since the build
  bool ready_ = false;
  // The current system matrix (set by compute) in float32 for the cycle's two products
  // (single_precision_symmetric.hpp: half the bytes; CG multiplies with it too at loose
  // tolerances, pcg.hpp).
  SinglePrecisionSymmetric A_single_;
  BlockJacobiPreconditioner diagonal_;
  std::uint64_t diagonal_assembly_ = 0;  // A_single_'s assembly_count() diagonal_ was computed at
  BlockProlongator prolongator_;  // P (3n x at most 6m) for P c and P^T r
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> coarse_;
  // The library's own supernodal factor, with or without CHOLMOD: its solve is as fast as the
  // same sweeps over CHOLMOD's factor, and its dense kernels factorize faster than CHOLMOD
  // with the reference BLAS a distribution installs by default (the first step at 122,880
  // tets: 1.21 -> 0.78 s on a Xeon with AVX-512).
  SparseCholesky coarse_factor_{SparseCholesky::Backend::Supernodal};
  Vec coarse_rhs_, coarse_solution_, turned_;
  // The diagonal terms (see the header comment): the coarse matrix with them, the recent
  // solves' (the factor covers them all: add_terms_to_coarse), and what the factor cost
  // since it was made.
  const DiagonalTerms* terms_ = nullptr;
  static constexpr int kRecentSolves = 4;
  // The terms of the last kRecentSolves - 1 solves, the latest at recent_latest_.
  std::array<DiagonalTerms, kRecentSolves - 1> recent_terms_;
  int recent_latest_ = 0;
  const SystemCoupling* coupling_ = nullptr;
  // The aggregate pairs beyond coarse_'s pattern in coarse_with_terms_'s (sorted, both
  // orders), where coarse_'s entries sit in it, and work space.
  std::vector<std::pair<int, int>> coupled_pairs_, needed_pairs_;
  std::vector<int> coarse_positions_;
  Vec coupled_product_;  // apply()'s C z
  std::vector<int> coarse_start_;  // first coarse DOF of each aggregate, + 1
  std::vector<char> node_mark_;    // work space: the nodes of this solve's terms
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> coarse_with_terms_;
  bool factored_with_terms_ = false;
  long applies_ = 0;  // in the current solve
  long fewest_applies_ = 0;  // in one solve since the factor
  long excess_applies_ = 0;  // the applications beyond them since the factor (see the source)
  long refactor_cost_in_applies_ = 10;
  // save_state's copy of the above, and the coarse values of the factor a failed call replaced.
  struct TermsState {
    std::array<DiagonalTerms, kRecentSolves - 1> recent_terms;
    int recent_latest = 0;
    bool factored_with_terms = false;
    long fewest_applies = 0, excess_applies = 0;
    int refactorizations = 0;
  } saved_;
  bool refactored_since_save_ = false;
  std::vector<double> saved_coarse_values_;
  std::vector<std::pair<int, int>> saved_pairs_;  // coupled_pairs_ then
  int refactorizations_ = 0;
  // The cycle's iterate and its product, four entries per node, in float32 for the float32
  // product (the iterate itself is kept in double in z).
  std::vector<float> z4_, y4_;
  double smoothing_weight_ = 0.0;  // 4 / (3 lambda_max(D^-1 A0)): the smoother contracts
};

}  // namespace corotate
