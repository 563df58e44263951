// Linear solvers on A = M + dt^2 K of a small elastic tet beam (SPD, condition number ~1e3):
// PCG reaches its tolerance with every preconditioner, the direct solver solves to round-off.
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "corotate/solvers/block_cholesky.hpp"
#include "corotate/solvers/coupled_matrix.hpp"
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/node_rotations.hpp"
#include "corotate/solvers/pcg.hpp"
#include "corotate/solvers/two_level_preconditioner.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

struct Problem {
  fixtures::Mesh mesh = fixtures::tet_beam(4, 2, 2);
  fixtures::System system = fixtures::implicit_system(mesh, Material{1e6, 0.3, 1000.0}, 0.01);
  Vec b = fixtures::random_matrix<Vec>(system.A.num_dofs(), 1);
  Vec exact = system.dense.llt().solve(b);
  double condition() const {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(system.dense, Eigen::EigenvaluesOnly);
    return eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
  }
};

double relative_residual(const BlockSparseMatrix& A, const Vec& x, const Vec& b) {
  Vec Ax(b.size());
  A.multiply(x, Ax);
  return (b - Ax).norm() / b.norm();
}

}  // namespace

TEST(test_system_is_symmetric_positive_definite) {
  const Problem p;
  CHECK((p.system.dense - p.system.dense.transpose()).cwiseAbs().maxCoeff() <=
        1e-15 * p.system.dense.cwiseAbs().maxCoeff());
  CHECK(p.system.dense.llt().info() == Eigen::Success);
  CHECK(p.condition() > 10);  // not trivially easy for CG
}

TEST(pcg_converges_with_every_preconditioner) {
  const Problem p;
  const double tolerance = 1e-10;
  // The recursively updated CG residual drifts from the true one by ~ eps * condition.
  const double drift = 100 * 2.2e-16 * p.condition();
  for (PreconditionerKind kind : {PreconditionerKind::None, PreconditionerKind::Jacobi, PreconditionerKind::BlockJacobi,
                                  PreconditionerKind::ReferenceFactor, PreconditionerKind::TwoLevel}) {
    std::printf("  %-16s", preconditioner_name(kind));
    PCG pcg(PCGSettings{10000, tolerance, false, kind});
    pcg.set_geometry(p.mesh.points);
    Vec x;
    const SolveStats stats = pcg.solve(p.system.A, p.b, x);
    std::printf(" %4d iterations, relative residual %.2e\n", stats.iterations, stats.relative_residual);
    CHECK(stats.converged);
    CHECK(stats.relative_residual <= tolerance);
    CHECK_NEAR(relative_residual(p.system.A, x, p.b), 0.0, tolerance + drift);
    // Error bound from the residual: |x - x*| / |x*| <= condition * relative residual.
    CHECK_NEAR((x - p.exact).norm() / p.exact.norm(), 0.0, p.condition() * (tolerance + drift));
    CHECK(stats.iterations > 0 && stats.iterations <= p.system.A.num_dofs());

    // Warm start from the answer: nothing left to do.
    PCG warm(PCGSettings{10000, 1e-6, true, kind});
    warm.set_geometry(p.mesh.points);
    Vec x0 = x;
    CHECK(warm.solve(p.system.A, p.b, x0).iterations == 0);
  }
}

TEST(pcg_preconditioners_cut_the_iterations) {
  const Problem p;
  auto iterations = [&](PreconditionerKind kind) {
    PCG pcg(PCGSettings{10000, 1e-8, false, kind});
    pcg.set_geometry(p.mesh.points);
    Vec x;
    return pcg.solve(p.system.A, p.b, x).iterations;
  };
  const int plain = iterations(PreconditionerKind::None);
  CHECK(iterations(PreconditionerKind::BlockJacobi) < plain);
  // A reused Cholesky factor of this very matrix is exact up to single-precision storage.
  CHECK(iterations(PreconditionerKind::ReferenceFactor) <= 5);
}

TEST(pcg_iteration_cap_stops_early) {
  const Problem p;
  PCG pcg(PCGSettings{3, 1e-12, false, PreconditionerKind::Jacobi});
  Vec x;
  const SolveStats stats = pcg.solve(p.system.A, p.b, x);
  CHECK(stats.iterations == 3);
  CHECK(!stats.converged);
  CHECK(stats.relative_residual > 1e-12);
}

// With the two-level preconditioner's float32 copy of A, CG solves a system within 6e-8 per
// entry of A: at a loose tolerance (>= kSinglePrecisionProductTolerance) it multiplies with
// the copy and its recursive residual then differs from the true one by about that much (in
// double the two agree to ~eps * condition); the true residual still meets the tolerance.
// Below it CG multiplies in double (pcg_converges_with_every_preconditioner solves to 1e-10,
// which the float copy could not).
TEST(pcg_multiplies_with_the_float_copy_only_at_loose_tolerances) {
  const Problem p;
  const double drift = 100 * 2.2e-16 * p.condition();
  for (const auto kind : {PreconditionerKind::TwoLevel, PreconditionerKind::ReferenceFactor})
    for (const double tolerance : {1e-3, 1e-5}) {
      const bool single = tolerance >= kSinglePrecisionProductTolerance;
      PCG pcg(PCGSettings{100, tolerance, false, kind});
      pcg.set_geometry(p.mesh.points);
      Vec x;
      const SolveStats stats = pcg.solve(p.system.A, p.b, x);
      const double true_residual = relative_residual(p.system.A, x, p.b);
      const double gap = std::abs(true_residual - stats.relative_residual);
      std::printf("  %s, tolerance %.0e: reported %.6e, true %.6e\n", preconditioner_name(kind), tolerance,
                  stats.relative_residual, true_residual);
      CHECK(stats.converged);
      CHECK(true_residual <= tolerance * (1 + 1e-3));
      if (single) CHECK(gap > 1e-11 && gap < 1e-6);
      else CHECK(gap <= drift);
      // The next step may assemble straight into the float32 copy only where CG uses it.
      CHECK((pcg.single_precision_target() != nullptr) == single);
    }
  // reference_factor keeps the copy for CG alone: told that CG multiplies in double, it makes
  // none (no conversion per step).
  for (const bool single : {true, false}) {
    ReferenceFactorPreconditioner factor;
    factor.set_single_precision_products(single);
    factor.compute(p.system.A);
    CHECK((factor.single_precision_matrix() != nullptr) == single);
    CHECK((factor.assembly_target() != nullptr) == single);
  }
}

TEST(block_cholesky_solves_in_double_and_in_float32_sums) {
  // The reused factor (float32 blocks) inverts A to float32 accuracy; summing in float32
  // (solve_single, four lanes per node) changes the answer by float32 round-off only.
  // Both forward sweeps of solve_single: pulling (a factor small enough to be kept by rows
  // too, the default here) and pushing (told to keep none).
  const Problem p;
  for (const size_t latency_bound_bytes : {BlockCholesky::kLatencyBoundBytes, size_t(0)}) {
    BlockCholesky factor;
    factor.factorize(p.system.A, latency_bound_bytes);
    const Index n = p.b.size();
    Vec x(n), xs(n);
    factor.solve(p.b, x);
    factor.solve_single(p.b, xs);
    CHECK(relative_residual(p.system.A, x, p.b) < 1e-5);
    CHECK(relative_residual(p.system.A, xs, p.b) < 1e-5);
    CHECK((x - p.exact).norm() < 1e-4 * p.exact.norm());
    CHECK((xs - x).norm() < 1e-5 * x.norm());
    CHECK((xs - x).norm() > 0);  // really summed in float32
    // Twice on the same right-hand side: the same answer (no state from the last solve).
    Vec again(n);
    factor.solve_single(p.b, again);
    CHECK(again == xs);
  }
}

TEST(block_cholesky_refactorizes_a_matrix_of_the_same_pattern_numerically) {
  // A second matrix of the same pattern (stiffer springs on some diagonal blocks, the
  // off-diagonal blocks scaled) keeps the ordering and structure: the same answers as a
  // factor built afresh, in both arrangements. An indefinite one of that pattern throws and
  // leaves the factor empty; a matrix of another pattern is factorized afresh.
  const Problem p;
  BlockSparseMatrix changed = p.system.A;
  for (Index i = 0; i < changed.num_nodes(); ++i)
    for (int e = changed.row_start()[i]; e < changed.row_start()[i + 1]; ++e)
      if (changed.columns()[e] == i) changed.block(e).diagonal().array() += 1e3 * double(i % 3);
      else changed.block(e) *= 1.0 + 0.05 * double((i + changed.columns()[e]) % 4);  // (symmetric)
  for (const size_t latency_bound_bytes : {BlockCholesky::kLatencyBoundBytes, size_t(0)}) {
    BlockCholesky kept, fresh;
    kept.factorize(p.system.A, latency_bound_bytes);
    kept.factorize(changed, latency_bound_bytes);
    fresh.factorize(changed, latency_bound_bytes);
    CHECK(kept.numeric_refactorizations() == 1 && fresh.numeric_refactorizations() == 0);
    CHECK(kept.order() == fresh.order() && kept.factor_blocks() == fresh.factor_blocks());
    const Index n = p.b.size();
    Vec x(n), expected(n), xs(n), expected_single(n);
    kept.solve(p.b, x);
    fresh.solve(p.b, expected);
    kept.solve_single(p.b, xs);
    fresh.solve_single(p.b, expected_single);
    CHECK((x - expected).norm() <= 1e-12 * expected.norm());
    CHECK((xs - expected_single).norm() <= 1e-6 * expected.norm());
    CHECK(relative_residual(changed, x, p.b) < 1e-5);
    // Back to the first matrix: numerically again, and its own answer.
    kept.factorize(p.system.A, latency_bound_bytes);
    kept.solve(p.b, x);
    CHECK(kept.numeric_refactorizations() == 2);
    CHECK((x - p.exact).norm() < 1e-4 * p.exact.norm());
    BlockSparseMatrix indefinite = p.system.A;
    indefinite.block(indefinite.diagonal_block(indefinite.num_nodes() - 1)) *= -1.0;
    CHECK_THROWS(kept.factorize(indefinite, latency_bound_bytes), NotPositiveDefinite);
    CHECK(kept.empty());
    kept.factorize(p.system.A, latency_bound_bytes);  // afresh after the failure
    CHECK(kept.numeric_refactorizations() == 2 && !kept.empty());
    kept.solve(p.b, x);
    CHECK((x - p.exact).norm() < 1e-4 * p.exact.norm());
  }
  // Another pattern (a larger mesh): afresh.
  const fixtures::Mesh larger = fixtures::tet_beam(5, 2, 2);
  const auto other = fixtures::implicit_system(larger, Material{1e6, 0.3, 1000.0}, 0.01);
  BlockCholesky factor;
  factor.factorize(p.system.A);
  factor.factorize(other.A);
  CHECK(factor.numeric_refactorizations() == 0);
  const Vec b = fixtures::random_matrix<Vec>(other.A.num_dofs(), 1);
  Vec x(b.size());
  factor.solve(b, x);
  CHECK(relative_residual(other.A, x, b) < 1e-5);
}

TEST(block_cholesky_prices_a_refactorization_in_solves) {
  // Column k's c_k off-diagonal blocks: c_k (c_k + 1) / 2 products of 27 multiply-adds to
  // factorize, 2 x 9 per block to solve. A chain of nodes (one block below each diagonal
  // block, whatever the order AMD picks): 27 / 18 = 1.5. Four nodes all coupled (columns of 3,
  // 2, 1 and 0 blocks): 27 * 10 / (18 * 6) = 2.5.
  const auto spd = [](BlockSparseMatrix A) {
    for (Index i = 0; i < A.num_nodes(); ++i)
      for (int e = A.row_start()[i]; e < A.row_start()[i + 1]; ++e)
        A.block(e) = A.columns()[e] == i ? Mat3(10 * Mat3::Identity()) : Mat3(-Mat3::Identity());
    return A;
  };
  BlockCholesky chain, dense;
  chain.factorize(spd(BlockSparseMatrix::from_pairs(
      6, {{0, 1}, {1, 0}, {1, 2}, {2, 1}, {2, 3}, {3, 2}, {3, 4}, {4, 3}, {4, 5}, {5, 4}})));
  std::vector<std::pair<int, int>> all;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (i != j) all.emplace_back(i, j);
  dense.factorize(spd(BlockSparseMatrix::from_pairs(4, all)));
  CHECK_NEAR(chain.refactorization_cost_in_solves(), 1.5, 1e-12);
  CHECK_NEAR(dense.refactorization_cost_in_solves(), 2.5, 1e-12);
}

TEST(block_cholesky_turned_solve_is_the_rotated_solve) {
  // solve(b, x, turn) = R A^-1 R^T b, R = diag(turn[i]): one rotation per node.
  const Problem p;
  const Index n = p.b.size(), nodes = n / 3;
  std::vector<Mat3> turn(nodes);
  Vec Rtb(n);
  for (Index i = 0; i < nodes; ++i) {
    turn[i] = Eigen::AngleAxisd(0.1 * double(i), Vec3(1, 2, 3 + double(i)).normalized()).toRotationMatrix();
    Rtb.segment<3>(3 * i) = turn[i].transpose() * p.b.segment<3>(3 * i);
  }
  for (const size_t latency_bound_bytes : {BlockCholesky::kLatencyBoundBytes, size_t(0)}) {
    BlockCholesky factor;
    factor.factorize(p.system.A, latency_bound_bytes);
    Vec plain(n), turned(n), turned_single(n);
    factor.solve(Rtb, plain);
    factor.solve(p.b, turned, turn.data());
    factor.solve_single(p.b, turned_single, turn.data());
    for (Index i = 0; i < nodes; ++i) {
      const Vec3 expected = turn[i] * plain.segment<3>(3 * i);
      CHECK((turned.segment<3>(3 * i) - expected).norm() <= 1e-12 * plain.norm());
      CHECK((turned_single.segment<3>(3 * i) - expected).norm() <= 1e-5 * plain.norm());
    }
  }
}

TEST(node_rotations_follow_each_stencil) {
  // A rigid rotation turns every node's stencil by it; a twist about the beam's axis turns
  // each cross-section by its own angle, and the nodes there by about that angle.
  const Problem p;
  NodeRotations rotations;
  rotations.build(p.system.A, p.mesh.points);
  CHECK(!rotations.rotated());
  const Mat3 R = Eigen::AngleAxisd(2.5, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  rotations.update(R * p.mesh.points);
  CHECK(rotations.rotated());
  for (const Mat3& Ri : rotations.rotations()) CHECK((Ri - R).norm() < 1e-6);  // to rough accuracy
  Nodes twisted = p.mesh.points;
  const double length = p.mesh.points.row(0).maxCoeff();
  for (Index i = 0; i < twisted.cols(); ++i) {
    const double angle = 0.6 * p.mesh.points(0, i) / length;  // about x, growing along it
    twisted.col(i) = Eigen::AngleAxisd(angle, Vec3::UnitX()) * p.mesh.points.col(i);
  }
  rotations.build(p.system.A, p.mesh.points);
  rotations.update(twisted);
  double worst = 0;
  for (Index i = 0; i < twisted.cols(); ++i) {
    const Eigen::AngleAxisd turned(rotations.rotations()[i]);
    const double expected = 0.6 * p.mesh.points(0, i) / length;
    worst = std::max(worst, std::abs(turned.angle() * turned.axis().x() - expected));
  }
  // Off by less than the twist across one of the beam's four cells (a stencil's reach): an
  // end node's stencil lies on one side of it. Without the rotations, 0.6 off at the far end.
  CHECK(worst < 0.6 / 4);
  Nodes wrong(3, twisted.cols() + 1);
  CHECK_THROWS(rotations.update(wrong), InvalidInput);
}

TEST(block_cholesky_orders_level_by_level_with_the_fill_of_amd) {
  // A small factor's order is AMD's rearranged by levels of the elimination tree: the same
  // fill (nonzeros of L) as AMD's order, every node after all of its descendants, levels
  // ascending.
  const fixtures::Mesh mesh = fixtures::tet_beam(8, 3, 3);
  const auto system = fixtures::implicit_system(mesh, Material{1e6, 0.3, 1000.0}, 0.01);
  const BlockSparseMatrix& A = system.A;
  const Index n = A.num_nodes();
  BlockCholesky factor;
  factor.factorize(A);
  using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  // L of the scalar matrix with its nodes in the given order (node order[k] at position k).
  const auto factor_in = [&](const std::vector<int>& order) {
    std::vector<int> position(n);
    for (Index k = 0; k < n; ++k) position[order[k]] = static_cast<int>(k);
    Sparse permuted(3 * n, 3 * n);
    std::vector<Eigen::Triplet<double, int>> t;
    for (Index i = 0; i < n; ++i)
      for (int e = A.row_start()[i]; e < A.row_start()[i + 1]; ++e)
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            t.emplace_back(3 * position[i] + r, 3 * position[A.columns()[e]] + c, A.block(e)(r, c));
    permuted.setFromTriplets(t.begin(), t.end());
    Eigen::SimplicialLLT<Sparse, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(permuted);
    CHECK(llt.info() == Eigen::Success);
    return Sparse(llt.matrixL());
  };
  Sparse graph(n, n);
  {
    std::vector<Eigen::Triplet<double, int>> t;
    for (Index i = 0; i < n; ++i)
      for (int e = A.row_start()[i]; e < A.row_start()[i + 1]; ++e) t.emplace_back(i, A.columns()[e], 1.0);
    graph.setFromTriplets(t.begin(), t.end());
  }
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> amd;
  Eigen::AMDOrdering<int>()(graph, amd);
  const std::vector<int> amd_order(amd.indices().data(), amd.indices().data() + n);
  const std::vector<int>& order = factor.order();
  CHECK(factor.arranged_for_latency());
  CHECK(order != amd_order);  // rearranged on this mesh
  BlockCholesky large;  // told it is too large to be arranged: AMD's order as it is
  large.factorize(A, 0);
  CHECK(!large.arranged_for_latency() && large.order() == amd_order);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (Index k = 0; k < n; ++k) CHECK(sorted[k] == k);  // a permutation
  const Sparse L = factor_in(order);
  CHECK(L.nonZeros() == factor_in(amd_order).nonZeros());
  // Elimination tree of L: a node's parent is the first node below it in its columns.
  std::vector<int> level(n, 0);
  for (Index k = 0; k < n; ++k) {
    int parent = -1;
    for (int c = 0; c < 3; ++c)
      for (Sparse::InnerIterator it(L, 3 * k + c); it; ++it)
        if (it.row() / 3 > k && (parent < 0 || it.row() / 3 < parent)) parent = it.row() / 3;
    if (parent >= 0) level[parent] = std::max(level[parent], level[k] + 1);
    if (k > 0) CHECK(level[k] >= level[k - 1]);  // final: all its children came before
  }
  CHECK(level[n - 1] > 0 && level[0] == 0);
}

TEST(block_jacobi_inverts_the_float32_diagonal_blocks_and_names_a_singular_one) {
  const Problem p;
  SinglePrecisionSymmetric single;
  single.assign(p.system.A);
  BlockJacobiPreconditioner from_single, from_double;
  from_single.compute(single);
  from_double.compute(p.system.A);
  for (Index i = 0; i < p.system.A.num_nodes(); ++i) {
    const Mat3& inv = from_single.inverse_block(i);
    CHECK(inv == inv.transpose());  // exactly symmetric
    CHECK((inv - from_double.inverse_block(i)).norm() < 1e-6 * from_double.inverse_block(i).norm());
  }
  BlockSparseMatrix singular = p.system.A;
  singular.block(singular.diagonal_block(7)).setZero();
  single.assign(singular);
  CHECK_THROWS(from_single.compute(single), NotPositiveDefinite);
  try {
    from_single.compute(single);
  } catch (const NotPositiveDefinite& e) {
    CHECK(std::string(e.what()).find("node 7") != std::string::npos);
  }
}

TEST(pcg_rejects_bad_settings) {
  CHECK_THROWS(PCG(PCGSettings{0, 1e-6, true, PreconditionerKind::Jacobi}), InvalidInput);
  CHECK_THROWS(PCG(PCGSettings{10, -1e-3, true, PreconditionerKind::Jacobi}), InvalidInput);
  CHECK_THROWS(PCG(PCGSettings{10, std::nan(""), true, PreconditionerKind::Jacobi}), InvalidInput);
  PCG by_default(PCGSettings{10, 0.0, true, PreconditionerKind::Jacobi});  // 0: the preconditioner's
}

TEST(pcg_default_tolerance_is_the_preconditioners) {
  // Tolerance 0 stops CG where the preconditioner says (2e-2 for two_level, 1e-2 otherwise),
  // and the stats say which tolerance was used; a set tolerance is used as it is.
  const Problem p;
  for (const auto kind : {PreconditionerKind::BlockJacobi, PreconditionerKind::TwoLevel}) {
    for (const double set : {0.0, 1e-3}) {
      PCG pcg(PCGSettings{200, set, false, kind});
      pcg.set_geometry(p.mesh.points);
      Vec x;
      const SolveStats st = pcg.solve(p.system.A, p.b, x);
      const double expected = set > 0 ? set : (kind == PreconditionerKind::TwoLevel ? 2e-2 : 1e-2);
      CHECK(st.tolerance == expected);
      CHECK(st.converged && st.relative_residual <= expected);
      CHECK(st.relative_residual > 0.1 * expected);  // it stopped there, not far below
    }
  }
}

TEST(direct_solver_solves_to_round_off) {
  const Problem p;
  DirectSolver direct;
  Vec x;
  const SolveStats stats = direct.solve(p.system.A, p.b, x);
  // LDL^T is backward stable: the residual is a small multiple of eps |A| |x|.
  const double scale = p.system.dense.norm() * x.norm() / p.b.norm();
  CHECK_NEAR(relative_residual(p.system.A, x, p.b), 0.0, 100 * 2.2e-16 * scale);
  CHECK_NEAR(stats.relative_residual, relative_residual(p.system.A, x, p.b), 1e-15 * scale);
  CHECK_NEAR((x - p.exact).norm() / p.exact.norm(), 0.0, 100 * 2.2e-16 * p.condition());
  // A second solve with new values reuses the analysis.
  BlockSparseMatrix A2 = p.system.A;
  A2.assign_scaled(2.0, p.system.A);
  direct.solve(A2, p.b, x);
  CHECK_NEAR((2 * x - p.exact).norm() / p.exact.norm(), 0.0, 100 * 2.2e-16 * p.condition());
}

TEST(direct_solver_rejects_an_indefinite_matrix) {
  const Problem p;
  BlockSparseMatrix A = p.system.A;
  A.assign_scaled(-1.0, p.system.A);
  DirectSolver direct;
  Vec x;
  CHECK_THROWS(direct.solve(A, p.b, x), SolverFailure);
}

TEST(pcg_built_once_is_invariant_under_a_rigid_rotation_when_given_the_positions) {
  // The system of a rigidly rotated body is A = R A0 R^T (blockwise; the mass is isotropic)
  // with right-hand side R b0 and answer R x0. A two-level hierarchy or a reference factor
  // built at rest and told the rotated positions turns with the body (its coarse level, or
  // the factor applied in each aggregate's frame): the same iterations and the rotated
  // answer. Without the positions the frozen preconditioner is wrong for the turned body and
  // CG needs many more iterations (the run-away of capped solves on swinging bodies).
  // Stiff (dt^2 K / M ~ 100 per unit cell, as the 0.3 m armadillo of E = 1 MPa): the coarse
  // level matters.
  fixtures::Mesh mesh = fixtures::tet_beam(12, 4, 4);
  for (Index i = 0; i < mesh.points.cols(); ++i)  // irregular: interior nodes jittered by 0.2
    if ((mesh.points.col(i).array() > 0).all() && (mesh.points.col(i).array() < Vec3(12, 4, 4).array()).all())
      mesh.points.col(i) += 0.2 * fixtures::random_matrix<Vec3>();
  const fixtures::System rest = fixtures::implicit_system(mesh, Material{1e9, 0.3, 1000.0}, 0.01);
  const Mat3 R = Eigen::AngleAxisd(2.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  BlockSparseMatrix turned = rest.A;
  for (Index k = 0; k < turned.num_blocks(); ++k) turned.block(int(k)) = R * rest.A.block(int(k)) * R.transpose();
  const Nodes turned_points = R * mesh.points;
  const Vec b0 = fixtures::random_matrix<Vec>(rest.A.num_dofs(), 1);
  Vec b = b0;
  for (Index i = 0; i < mesh.points.cols(); ++i) b.segment<3>(3 * i) = R * b0.segment<3>(3 * i);

  for (PreconditionerKind kind : {PreconditionerKind::TwoLevel, PreconditionerKind::ReferenceFactor}) {
    auto solve_turned = [&](bool tell_positions, Vec& x0, Vec& x) {
      PCG pcg(PCGSettings{1000, 1e-8, false, kind});
      pcg.set_geometry(mesh.points);
      pcg.set_positions(mesh.points);
      const int at_rest = pcg.solve(rest.A, b0, x0).iterations;  // builds it at rest
      if (tell_positions) pcg.set_positions(turned_points);
      return std::make_pair(at_rest, pcg.solve(turned, b, x).iterations);
    };
    Vec x0, x;
    const auto [at_rest, turning] = solve_turned(true, x0, x);
    std::printf("  %-16s at rest %d iterations, turned with positions %d", preconditioner_name(kind), at_rest, turning);
    CHECK(turning == at_rest);
    for (Index i = 0; i < mesh.points.cols(); ++i)
      CHECK_NEAR((x.segment<3>(3 * i) - R * x0.segment<3>(3 * i)).norm(), 0.0, 1e-9 * x0.norm());
    Vec y0, y;
    const int frozen = solve_turned(false, y0, y).second;
    std::printf(", frozen %d\n", frozen);
    CHECK(frozen >= 2 * at_rest);

    PCG pcg(PCGSettings{1000, 1e-8, false, kind});
    pcg.set_geometry(mesh.points);
    pcg.set_positions(Nodes::Zero(3, 5));  // positions of another mesh
    CHECK_THROWS(pcg.solve(rest.A, b0, x), InvalidInput);
  }
}

TEST(auto_preconditioner_factorizes_small_systems_and_builds_two_levels_for_large_ones) {
  // Unit diagonal on a beam's pattern: the choice depends on the size alone.
  for (const auto& [cells, expected] :
       {std::make_pair(std::array<int, 3>{4, 2, 2}, PreconditionerKind::ReferenceFactor),
        std::make_pair(std::array<int, 3>{20, 10, 10}, PreconditionerKind::TwoLevel)}) {
    const fixtures::Mesh mesh = fixtures::tet_beam(cells[0], cells[1], cells[2]);
    BlockSparseMatrix A = BlockSparseMatrix::from_cells(mesh.points.cols(), mesh.cells);
    A.set_zero();
    for (Index i = 0; i < A.num_nodes(); ++i) A.block(A.diagonal_block(i)).setIdentity();
    CHECK((A.num_dofs() < kAutoFactorDofs) == (expected == PreconditionerKind::ReferenceFactor));
    AutoPreconditioner pc;
    CHECK(pc.chosen() == PreconditionerKind::Auto);
    pc.set_geometry(mesh.points);
    pc.compute(A);
    CHECK(pc.chosen() == expected);
    const Vec r = fixtures::random_matrix<Vec>(A.num_dofs(), 1);
    Vec z(A.num_dofs());
    pc.apply(r, z);
    if (expected == PreconditionerKind::ReferenceFactor)
      CHECK_NEAR((z - r).norm(), 0.0, 1e-6 * r.norm());  // A = I exactly (a float factor: 1e-6)
    else CHECK(z.allFinite() && r.dot(z) > 0);  // a V-cycle: SPD, not exact
    // A reset chooses afresh, with the geometry it was given before (the two-level needs it).
    pc.reset();
    CHECK(pc.chosen() == PreconditionerKind::Auto);
    pc.compute(A);
    CHECK(pc.chosen() == expected);
  }
  CHECK(PCGSettings{}.preconditioner == PreconditionerKind::Auto);
}

TEST(reference_factor_refactorizes_after_a_solve_that_ends_at_its_cap) {
  const Problem p;
  ReferenceFactorPreconditioner pc;
  pc.compute(p.system.A);
  pc.solved(true);
  pc.compute(p.system.A);
  CHECK(pc.factorizations() == 1);  // converged: the factor is kept
  pc.solved(false);
  pc.compute(p.system.A);
  CHECK(pc.factorizations() == 2);  // at the cap: factorized afresh, once
  pc.compute(p.system.A);
  CHECK(pc.factorizations() == 2);
  // An indefinite matrix at the refresh is reported, not factorized into NaN.
  BlockSparseMatrix indefinite = p.system.A;
  indefinite.assign_scaled(-1.0, p.system.A);
  pc.solved(false);
  CHECK_THROWS(pc.compute(indefinite), NotPositiveDefinite);
}

TEST(reference_factor_restores_a_factor_refreshed_in_a_failed_call) {
  // save_state, a capped solve, a refresh at another matrix, restore_state: the factor
  // applied afterwards is the first one again (the same z, to the bit), and the next
  // compute does not refactorize (the refresh flag restored too).
  const Problem p;
  BlockSparseMatrix other = p.system.A;
  other.assign_scaled(2.0, p.system.A);
  ReferenceFactorPreconditioner pc, twin;
  pc.compute(p.system.A);
  twin.compute(p.system.A);
  pc.save_state();
  pc.solved(false);
  pc.compute(other);
  CHECK(pc.factorizations() == 2);
  pc.restore_state();
  CHECK(pc.factorizations() == 1);
  const Vec r = fixtures::random_matrix<Vec>(p.system.A.num_dofs(), 1);
  Vec z(r.size()), z_twin(r.size());  // (apply writes into a sized vector)
  pc.compute(p.system.A);
  twin.compute(p.system.A);
  CHECK(pc.factorizations() == 1);
  pc.apply(r, z);
  twin.apply(r, z_twin);
  CHECK(z == z_twin);
}

TEST(a_warm_start_that_only_just_meets_the_tolerance_still_iterates) {
  // Taking last step's answer as it is re-applies its error (the warm start's lagged force);
  // a warm start is accepted without iterating only when it beats the tolerance 100-fold.
  const Problem p;
  for (const auto& [relative_error, iterations] : {std::make_pair(1e-9, 0), std::make_pair(1e-4, 1)}) {
    PCG pcg(PCGSettings{1000, 1e-2, true, PreconditionerKind::ReferenceFactor});
    Vec x = p.exact + relative_error * p.exact.norm() * fixtures::random_matrix<Vec>(p.exact.size(), 1).normalized();
    const double start = relative_residual(p.system.A, x, p.b);
    CHECK(start < 1e-2);  // the start meets the tolerance already
    const SolveStats stats = pcg.solve(p.system.A, p.b, x);
    std::printf("  start residual %.1e: %d iteration(s)\n", start, stats.iterations);
    CHECK(stats.iterations == iterations);
    CHECK(relative_residual(p.system.A, x, p.b) <= std::max(start, 1e-2));
  }
}

TEST(preconditioners_ask_for_the_lower_blocks_only_when_they_build) {
  // The step assembles only the blocks multiply_symmetric reads unless the solve needs more
  // (Request::lower_blocks): a preconditioner that factorizes or builds a hierarchy reads
  // the whole matrix, and only then.
  const Problem p;
  CHECK(!BlockJacobiPreconditioner().needs_lower_blocks());
  CHECK(!JacobiPreconditioner().needs_lower_blocks());
  ReferenceFactorPreconditioner factor;
  CHECK(factor.needs_lower_blocks());
  factor.compute(p.system.A);
  CHECK(!factor.needs_lower_blocks());
  factor.solved(false);  // at the cap: the next compute factorizes again
  CHECK(factor.needs_lower_blocks());
  factor.compute(p.system.A);
  CHECK(!factor.needs_lower_blocks());
  TwoLevelPreconditioner two_level;
  two_level.set_geometry(p.mesh.points);
  CHECK(two_level.needs_lower_blocks());
  two_level.compute(p.system.A);
  CHECK(!two_level.needs_lower_blocks());
  two_level.reset();
  CHECK(two_level.needs_lower_blocks());
  PCG pcg;  // auto: asks before it has chosen, then as the one it chose
  CHECK(pcg.needs_lower_blocks());
  Vec x = Vec::Zero(p.b.size());
  pcg.solve(p.system.A, p.b, x);
  CHECK(!pcg.needs_lower_blocks());
  CHECK(DirectSolver().needs_lower_blocks());
}

namespace {

// A free beam's system with stiff contact springs k n n^T (k a hundred times the node's own
// diagonal) on its floor (z = 0) and on one side (y = 0), as the contact step adds them.
struct ContactProblem {
  fixtures::Mesh mesh = fixtures::tet_beam(12, 3, 3);
  fixtures::System own = fixtures::implicit_system(mesh, Material{1e7, 0.3, 1000.0}, 0.01);
  DiagonalTerms floor, side;
  BlockSparseMatrix with(const std::vector<const DiagonalTerms*>& all) const {
    BlockSparseMatrix A = own.A;
    for (const DiagonalTerms* terms : all)
      for (size_t k = 0; k < terms->nodes.size(); ++k) A.block(A.diagonal_block(terms->nodes[k])) += terms->blocks[k];
    return A;
  }
  ContactProblem() {
    for (Index i = 0; i < mesh.points.cols(); ++i) {
      const double k = 100 * own.A.block(own.A.diagonal_block(i)).trace() / 3;
      if (mesh.points(2, i) == 0) {
        floor.nodes.push_back(i);
        floor.blocks.push_back(k * Vec3::UnitZ() * Vec3::UnitZ().transpose());
      }
      if (mesh.points(1, i) == 0) {
        side.nodes.push_back(i);
        side.blocks.push_back(k * Vec3::UnitY() * Vec3::UnitY().transpose());
      }
    }
  }
};

}  // namespace

TEST(two_level_coarse_level_takes_the_contact_terms) {
  // Without the springs in its coarse matrix, the coarse correction pushes whole aggregates
  // into the floor that holds them.
  const ContactProblem p;
  DiagonalTerms both = p.floor;
  both.nodes.insert(both.nodes.end(), p.side.nodes.begin(), p.side.nodes.end());
  both.blocks.insert(both.blocks.end(), p.side.blocks.begin(), p.side.blocks.end());
  const BlockSparseMatrix A = p.with({&both});
  const Vec b = fixtures::random_matrix<Vec>(A.num_dofs(), 1);
  Eigen::MatrixXd dense = p.own.dense;
  for (size_t k = 0; k < both.nodes.size(); ++k)
    dense.block<3, 3>(3 * both.nodes[k], 3 * both.nodes[k]) += both.blocks[k];
  const Vec exact = dense.llt().solve(b);
  auto solve = [&](bool build_without, bool tell) {
    PCG pcg(PCGSettings{2000, 1e-9, false, PreconditionerKind::TwoLevel});
    pcg.set_geometry(p.mesh.points);
    Vec x;
    if (build_without) pcg.solve(p.own.A, b, x);  // the hierarchy from the body's own system
    if (tell) pcg.set_diagonal_terms(&both);
    const int iterations = pcg.solve(A, b, x).iterations;
    CHECK_NEAR((x - exact).norm(), 0.0, 1e-6 * exact.norm());
    return iterations;
  };
  const int blind = solve(true, false), told = solve(true, true), built_with = solve(false, true);
  std::printf("  CG to 1e-9: %d iterations without the terms, %d with; %d with the hierarchy built on them\n", blind,
              told, built_with);
  CHECK(3 * told <= blind);
  // The hierarchy leaves the first system's terms out: the same preconditioner either way.
  CHECK(built_with == told);
}

TEST(two_level_refactorizes_for_contact_terms_only_when_it_pays) {
  const ContactProblem p;
  const BlockSparseMatrix on_floor = p.with({&p.floor}), on_side = p.with({&p.side});
  const Vec b = fixtures::random_matrix<Vec>(on_floor.num_dofs(), 1);
  TwoLevelPreconditioner pc;
  pc.set_geometry(p.mesh.points);
  auto solve = [&](const BlockSparseMatrix& A, const DiagonalTerms* terms) {
    pc.set_diagonal_terms(terms);
    pc.compute(A);
    // a fixed count of applications per solve, like a capped CG: what the factor costs
    Vec r = b, z;
    for (int k = 0; k < (terms == &p.side ? 25 : 3); ++k) pc.apply(r, z);
    pc.solved(true);
  };
  solve(p.own.A, nullptr);
  CHECK(pc.coarse_refactorizations() == 0);  // no terms: the factor of the build
  solve(on_floor, &p.floor);
  CHECK(pc.coarse_refactorizations() == 1);  // the first terms
  for (int k = 0; k < 20; ++k) solve(on_floor, &p.floor);
  CHECK(pc.coarse_refactorizations() == 1);  // the same terms, as cheap as the first solve
  // Other terms whose solves cost more (25 applications against 3) refactorize once the
  // excess adds up to a refactorization's worth (coarse unknowns / 30, at least 10).
  int solves = 0;
  while (pc.coarse_refactorizations() == 1 && solves < 50) {
    solve(on_side, &p.side);
    ++solves;
  }
  std::printf("  refactorized after %d solves with other terms\n", solves);
  CHECK(pc.coarse_refactorizations() == 2);
  CHECK(solves >= 2 && solves <= 3);
}

TEST(two_level_coarse_factor_holds_the_contacts_of_the_recent_solves) {
  // Contacts that flicker (the top edges of a beam grazing the walls it lies between) are in
  // the coarse factor in every phase: it holds each node's latest terms from the last few
  // solves, not this solve's alone, nor the last solve's as well (which of the flickering
  // contacts the factor then held decided between 2.6 and 4.0 CG iterations per step).
  // Three disjoint sets in turn; the factor made at the third equals one made of all three.
  const ContactProblem p;
  auto part = [&](auto keep) {  // a spring k n n^T on each node `keep` takes
    DiagonalTerms terms;
    for (Index i = 0; i < p.mesh.points.cols(); ++i)
      if (keep(p.mesh.points.col(i))) {
        const double k = 100 * p.own.A.block(p.own.A.diagonal_block(i)).trace() / 3;
        terms.nodes.push_back(i);
        terms.blocks.push_back(k * Vec3::UnitY() * Vec3::UnitY().transpose());
      }
    return terms;
  };
  const double top = p.mesh.points.row(2).maxCoeff();
  const DiagonalTerms floor = part([](const Vec3& x) { return x.z() == 0; });
  const DiagonalTerms roof = part([&](const Vec3& x) { return x.z() == top; });
  const DiagonalTerms side = part([&](const Vec3& x) { return x.y() == 0 && x.z() != 0 && x.z() != top; });
  DiagonalTerms all = floor;
  for (const DiagonalTerms* t : {&side, &roof}) {
    all.nodes.insert(all.nodes.end(), t->nodes.begin(), t->nodes.end());
    all.blocks.insert(all.blocks.end(), t->blocks.begin(), t->blocks.end());
  }
  CHECK(!floor.empty() && !roof.empty() && !side.empty());
  const BlockSparseMatrix on_floor = p.with({&floor});
  const Vec r = fixtures::random_matrix<Vec>(on_floor.num_dofs(), 1);
  TwoLevelPreconditioner flickering, told;
  for (TwoLevelPreconditioner* pc : {&flickering, &told}) {
    pc->set_geometry(p.mesh.points);
    pc->compute(p.own.A);  // the hierarchy, without terms
    pc->solved(true);
  }
  auto solve = [&](const DiagonalTerms& terms, int applications) {
    flickering.set_diagonal_terms(&terms);
    flickering.compute(p.with({&terms}));
    Vec z;
    for (int k = 0; k < applications; ++k) flickering.apply(r, z);
    flickering.solved(true);
  };
  solve(floor, 3);   // the first terms: factorized
  solve(side, 3);
  solve(roof, 60);   // dear: the next solve refactorizes
  CHECK(flickering.coarse_refactorizations() == 1);
  flickering.set_diagonal_terms(&floor);
  flickering.compute(on_floor);
  CHECK(flickering.coarse_refactorizations() == 2);
  told.set_diagonal_terms(&all);
  told.compute(on_floor);  // (the same fine matrix: only the coarse factor differs)
  CHECK(told.coarse_refactorizations() == 1);
  Vec z_flickering, z_told;
  flickering.apply(r, z_flickering);
  told.apply(r, z_told);
  std::printf("  apart %.2g of the answer\n", (z_flickering - z_told).norm() / z_told.norm());
  CHECK((z_flickering - z_told).norm() <= 1e-9 * z_told.norm());
}

TEST(two_level_restores_a_contact_factor_refactorized_in_a_failed_call) {
  // A call that refactorized the coarse level for other terms and then failed leaves the
  // preconditioner as a twin that never made it: the same output to the last bit.
  const ContactProblem p;
  const BlockSparseMatrix on_floor = p.with({&p.floor}), on_side = p.with({&p.side});
  const Vec r = fixtures::random_matrix<Vec>(on_floor.num_dofs(), 1);
  TwoLevelPreconditioner twin, failed;
  Vec z;
  for (TwoLevelPreconditioner* pc : {&twin, &failed}) {
    pc->set_geometry(p.mesh.points);
    pc->set_diagonal_terms(&p.floor);
    pc->compute(on_floor);
    pc->apply(r, z);
    pc->solved(true);
  }
  failed.save_state();
  failed.set_diagonal_terms(&p.side);
  for (int k = 0; k < 5; ++k) {  // costly solves: it refactorizes for the side's terms
    failed.compute(on_side);
    for (int a = 0; a < 25; ++a) failed.apply(r, z);
    failed.solved(false);
  }
  CHECK(failed.coarse_refactorizations() == 2);
  failed.restore_state();
  CHECK(failed.coarse_refactorizations() == 1);
  Vec z_twin, z_failed;
  for (auto [pc, out] : {std::make_pair(&twin, &z_twin), std::make_pair(&failed, &z_failed)}) {
    pc->set_diagonal_terms(&p.floor);
    pc->compute(on_floor);
    pc->apply(r, *out);
  }
  CHECK(z_twin == z_failed);
}

namespace {

// Stiff springs between nodes that share no element (the beam's ends pressed together, and
// its two sides, as two parts in contact are): each adds H = k n n^T to both diagonal blocks
// (in A) and -H to the blocks between them (the coupling C, outside A's pattern).
struct CoupledProblem final : SystemCoupling {
  ContactProblem base;
  std::vector<std::pair<Index, Index>> springs;
  std::vector<Mat3> stiffness;
  BlockSparseMatrix A = base.own.A;
  Eigen::MatrixXd dense = base.own.dense;
  CoupledProblem() {
    const Nodes& x = base.mesh.points;
    const Vec3 far = x.rowwise().maxCoeff();
    const auto facing = [&](Index i, Index j, int axis) {
      for (int d = 0; d < 3; ++d)
        if (d == axis ? (x(d, i) != 0 || x(d, j) != far[d]) : x(d, i) != x(d, j)) return false;
      return true;
    };
    for (Index i = 0; i < x.cols(); ++i)
      for (Index j = 0; j < x.cols(); ++j)
        if (facing(i, j, 0) || facing(i, j, 1)) {
          const double k = 100 * A.block(A.diagonal_block(i)).trace() / 3;
          const Vec3 n = Vec3(1, 0.3, -0.2).normalized();
          springs.emplace_back(i, j);
          stiffness.push_back(k * n * n.transpose());
        }
    for (size_t s = 0; s < springs.size(); ++s) {
      const auto [i, j] = springs[s];
      A.block(A.diagonal_block(i)) += stiffness[s];
      A.block(A.diagonal_block(j)) += stiffness[s];
      dense.block<3, 3>(3 * i, 3 * i) += stiffness[s];
      dense.block<3, 3>(3 * j, 3 * j) += stiffness[s];
      dense.block<3, 3>(3 * i, 3 * j) -= stiffness[s];
      dense.block<3, 3>(3 * j, 3 * i) -= stiffness[s];
    }
  }
  void multiply_add(const Vec& x, Vec& y) const override {
    for (size_t s = 0; s < springs.size(); ++s) {
      const auto [i, j] = springs[s];
      y.segment<3>(3 * i) -= stiffness[s] * x.segment<3>(3 * j);
      y.segment<3>(3 * j) -= stiffness[s] * x.segment<3>(3 * i);
    }
  }
  void for_each_block(const std::function<void(Index, Index, const Mat3&)>& visit) const override {
    for (size_t s = 0; s < springs.size(); ++s) {
      visit(springs[s].first, springs[s].second, -stiffness[s]);
      visit(springs[s].second, springs[s].first, -stiffness[s]);
    }
  }
};

}  // namespace

TEST(a_matrix_with_its_coupling_is_a_plus_c) {
  const CoupledProblem p;
  CHECK(!p.springs.empty());
  CHECK(p.A.block_index(p.springs[0].first, p.springs[0].second) < 0);  // outside A's pattern
  const BlockSparseMatrix joined = with_coupling(p.A, p);
  const Vec x = fixtures::random_matrix<Vec>(p.A.num_dofs(), 1);
  Vec y(x.size());
  joined.multiply(x, y);
  CHECK_NEAR((y - p.dense * x).norm(), 0.0, 1e-12 * (p.dense * x).norm());
}

TEST(reference_factor_and_direct_solver_take_the_coupling) {
  // A factor of A alone leaves CG an outlying eigenvalue per spring; a factor of A + C
  // leaves it nothing to find.
  const CoupledProblem p;
  const Vec b = fixtures::random_matrix<Vec>(p.A.num_dofs(), 1);
  const Vec exact = p.dense.llt().solve(b);
  PCG pcg(PCGSettings{2000, 1e-9, false, PreconditionerKind::ReferenceFactor});
  Vec x;
  pcg.solve(p.base.own.A, b, x);  // factorized without the springs
  pcg.set_coupling(&p);
  const int blind = pcg.solve(p.A, b, x).iterations;  // the old factor; asks for a new one
  CHECK_NEAR((x - exact).norm(), 0.0, 1e-7 * exact.norm());
  const int told = pcg.solve(p.A, b, x).iterations;  // refactorized with the coupling
  CHECK_NEAR((x - exact).norm(), 0.0, 1e-7 * exact.norm());
  std::printf("  CG to 1e-9 with %zu springs: %d iterations on A's factor, %d on A + C's\n", p.springs.size(), blind,
              told);
  CHECK(blind > 10 && told <= 3);

  DirectSolver direct;
  direct.set_coupling(&p);
  const SolveStats stats = direct.solve(p.A, b, x);
  CHECK(stats.iterations == 0);
  CHECK_NEAR((x - exact).norm(), 0.0, 1e-9 * exact.norm());
}

TEST(reference_factor_refactorizes_when_it_pays) {
  const ContactProblem p;
  const BlockSparseMatrix on_floor = p.with({&p.floor}), on_side = p.with({&p.side});
  const Vec b = fixtures::random_matrix<Vec>(on_floor.num_dofs(), 1);
  ReferenceFactorPreconditioner pc;
  // A fixed count of applications per solve stands for what CG needed.
  auto solve = [&](const BlockSparseMatrix& A, const DiagonalTerms* terms, int applications) {
    pc.set_diagonal_terms(terms);
    pc.compute(A);
    Vec r = b, z(b.size());
    for (int k = 0; k < applications; ++k) pc.apply(r, z);
    pc.solved(true);
  };
  // Solves that cost more than the fewest since the factor (5 applications against 3: an
  // excess of one each beyond the slack of one) refactorize once the excess adds up to what a
  // refactorization costs, and not before: a body that settled far from the state it was
  // factorized at (Table 1's cage sagging under gravity from rest), or contacts moved.
  auto solves_until_refresh = [&](const BlockSparseMatrix& A, const DiagonalTerms* terms) {
    const int before = pc.factorizations();
    int solves = 0;
    while (pc.factorizations() == before && solves < 50) {
      solve(A, terms, 5);
      ++solves;
    }
    return solves;
  };
  solve(p.own.A, nullptr, 3);
  solve(p.own.A, nullptr, 4);
  CHECK(pc.factorizations() == 1);  // one more application is within the slack
  const double cost = ReferenceFactorPreconditioner::kRefreshCostScale * pc.factor_cost_in_solves();
  std::printf("  refresh threshold %.2f applications\n", cost);
  CHECK(cost > 2);  // (the counts below are not trivially 2 or 3)
  const int without_contacts = solves_until_refresh(p.own.A, nullptr);
  std::printf("  refactorized after %d dearer solves without contacts\n", without_contacts);
  CHECK(without_contacts == 1 + static_cast<int>(std::ceil(cost)));
  CHECK(pc.factorizations() == 2);
  for (int k = 0; k < 20; ++k) solve(p.own.A, nullptr, 3);
  CHECK(pc.factorizations() == 2);  // as cheap as the fewest: the factor stays
  solve(on_floor, &p.floor, 3);
  CHECK(pc.factorizations() == 2);  // the first contacts ask for one...
  solve(on_floor, &p.floor, 3);
  CHECK(pc.factorizations() == 3);  // ...which the next solve makes
  for (int k = 0; k < 20; ++k) solve(on_floor, &p.floor, 3);
  CHECK(pc.factorizations() == 3);  // the same contacts, as cheap as the first solve
  const int other_contacts = solves_until_refresh(on_side, &p.side);
  std::printf("  refactorized after %d solves with other contacts\n", other_contacts);
  CHECK(other_contacts == 1 + static_cast<int>(std::ceil(cost)));
  CHECK(pc.factorizations() == 4);
}
