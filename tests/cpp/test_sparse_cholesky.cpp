// The direct solver's three backends, SuiteSparse CHOLMOD (when the build found it), the
// library's own supernodal factor and Eigen's SimplicialLDLT, solve the same systems to
// round-off (the supernodal factors through our own triangular sweeps), and all refuse an
// indefinite one; Auto picks by size and build.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "corotate/parallel.hpp"
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"
#include "corotate/solvers/supernodal_cholesky.hpp"
#include "corotate/solvers/supernodal_solve.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

TEST(auto_takes_a_supernodal_factor_for_large_systems_only) {
  // Below kSupernodalFromDofs supernodes are too small for dense kernels to pay (see
  // sparse_cholesky.hpp): Eigen's SimplicialLDLT factorizes faster.
  for (const Index n : {Index(300), SparseCholesky::kSupernodalFromDofs}) {
    SparseCholesky::Matrix identity(n, n);
    identity.setIdentity();
    SparseCholesky automatic;
    CHECK(std::string(automatic.backend_name()) == "auto");
    automatic.analyze(identity);
    const std::string large = SparseCholesky::have_cholmod() ? "cholmod" : "supernodal";
    CHECK(automatic.backend_name() == (n >= SparseCholesky::kSupernodalFromDofs ? large : std::string("eigen")));
    CHECK(automatic.factorize(identity));
    Vec x;
    automatic.solve(Vec::Ones(n), x);
    CHECK((x - Vec::Ones(n)).norm() == 0.0);
  }
}

namespace {

std::vector<SparseCholesky::Backend> backends() {
  std::vector<SparseCholesky::Backend> all{SparseCholesky::Backend::Eigen, SparseCholesky::Backend::Supernodal};
  if (SparseCholesky::have_cholmod()) all.push_back(SparseCholesky::Backend::Cholmod);
  return all;
}

}  // namespace

TEST(every_direct_backend_solves_to_round_off_and_refuses_indefinite_systems) {
  if (!SparseCholesky::have_cholmod()) {
    std::puts("  CHOLMOD not built (apt-get install libsuitesparse-dev): checking the other two");
    CHECK_THROWS(SparseCholesky(SparseCholesky::Backend::Cholmod), InvalidInput);
  }
  // A = M + dt^2 K of a 6 x 3 x 3 tet beam (no fixed nodes: M makes it definite).
  const auto system = fixtures::implicit_system(fixtures::tet_beam(6, 3, 3), Material{1e6, 0.3, 1000.0}, 1e-2);
  const Index n = system.A.num_dofs();
  const Vec b0 = fixtures::random_matrix<Vec>(n, 1);
  const Vec exact = system.dense.ldlt().solve(b0);
  for (const auto backend : backends()) {
    DirectSolver solver(backend);
    Vec b = b0, x;
    for (int round = 0; round < 2; ++round) {  // the second reuses the symbolic analysis
      const SolveStats stats = solver.solve(system.A, b, x);
      CHECK(stats.relative_residual < 1e-13);
      CHECK((x - (round == 0 ? 1.0 : -2.0) * exact).norm() <= 1e-12 * x.norm());
      b *= -2.0;
    }
    // An indefinite matrix is refused.
    BlockSparseMatrix indefinite = system.A;
    indefinite.block(indefinite.diagonal_block(3))(0, 0) = -1e9;
    CHECK_THROWS(solver.solve(indefinite, b, x), NotPositiveDefinite);
    // An empty system (a two-level coarse space with every DOF fixed) is solved, not a crash.
    SparseCholesky empty(backend);
    const SparseCholesky::Matrix none(0, 0);
    empty.analyze(none);
    CHECK(empty.factorize(none));
    Vec x_none;
    empty.solve(Vec(0), x_none);
    CHECK(x_none.size() == 0);
  }
  // The single-precision solve of the supernodal factors (a preconditioner's): float
  // round-off times the condition number (~1e3 here), and really float.
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> scalar;
  system.A.copy_to(scalar);
  for (const auto backend : backends()) {
    if (backend == SparseCholesky::Backend::Eigen) continue;
    SparseCholesky single(backend);
    single.set_single_precision_solve(true);
    single.analyze(scalar);
    CHECK(single.factorize(scalar));
    Vec x_single;
    single.solve(b0, x_single);
    const double error = (x_single - exact).norm() / exact.norm();
    CHECK(error < 1e-4 && error > 1e-12);
  }
}

TEST(supernodal_factor_of_an_unstructured_matrix_is_exact) {
  // Not 3 x 3 blocked: a random sparse SPD matrix (a random graph's Laplacian plus a random
  // diagonal), so scalar columns, relaxed supernodes and several trees all occur; and a
  // second pattern analysed by the same object.
  for (const int n : {1, 7, 60, 400}) {
    std::vector<Eigen::Triplet<double, int>> t;
    Vec diagonal = Vec::Constant(n, 0.5);
    for (int e = 0; e < 3 * n; ++e) {
      const int i = static_cast<int>(fixtures::uniform(0, n - 1e-9)),
                j = static_cast<int>(fixtures::uniform(0, n - 1e-9));
      if (i == j || (i + j) % 5 == 0) continue;  // some disconnected pieces
      const double w = fixtures::uniform(0.1, 1.0);
      t.emplace_back(i, j, -w), t.emplace_back(j, i, -w);
      diagonal[i] += w, diagonal[j] += w;
    }
    for (int i = 0; i < n; ++i) t.emplace_back(i, i, diagonal[i] + fixtures::uniform(0.0, 1.0));
    SparseCholesky::Matrix A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    SupernodalCholesky cholesky;
    cholesky.analyze(A);
    CHECK(cholesky.factorize(A));
    const SupernodalFactor& L = cholesky.factor();
    // L L^T equals P A P^T entry by entry.
    Eigen::MatrixXd dense_L = Eigen::MatrixXd::Zero(n, n);
    for (int s = 0; s < L.nsuper; ++s) {
      const int cols = L.super[s + 1] - L.super[s], height = L.pi[s + 1] - L.pi[s];
      for (int c = 0; c < cols; ++c)
        for (int r = c; r < height; ++r)
          dense_L(L.rows[L.pi[s] + r], L.super[s] + c) = cholesky.values()[L.px[s] + c * height + r];
    }
    Eigen::MatrixXd permuted(n, n);
    const Eigen::MatrixXd dense_A = Eigen::MatrixXd(A);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) permuted(i, j) = dense_A(L.perm[i], L.perm[j]);
    CHECK((dense_L * dense_L.transpose() - permuted).norm() <= 1e-13 * permuted.norm());
    // supernodal_solve with it
    const Vec b = fixtures::random_matrix<Vec>(n, 1);
    Vec x;
    SupernodalWork<double> work;
    supernodal_solve(L, SupernodalSplit::of(L), cholesky.values(), b, x, work);
    CHECK((dense_A * x - b).norm() <= 1e-12 * b.norm());
    // A new pattern is refused until analysed.
    SparseCholesky::Matrix other = A;
    other.coeffRef(0, n - 1) += 0.0;
    if (other.nonZeros() != A.nonZeros()) CHECK_THROWS(cholesky.factorize(other), InvalidInput);
    // NaN is no factor.
    SparseCholesky::Matrix broken = A;
    broken.valuePtr()[0] = std::numeric_limits<double>::quiet_NaN();
    CHECK(!cholesky.factorize(broken));
  }
}

namespace {

// A hand-made supernodal factor: one column per supernode, a dense lower-triangular L whose
// pattern gives the elimination tree parent[] (each column's below-diagonal rows are its
// ancestors), and no permutation.
struct HandFactor {
  std::vector<int> perm, super, pi, px, rows;
  std::vector<double> values;
  Eigen::MatrixXd dense;
  SupernodalFactor view() const {
    SupernodalFactor f;
    f.n = f.nsuper = static_cast<Index>(perm.size());
    f.perm = perm.data(), f.super = super.data(), f.pi = pi.data(), f.px = px.data(), f.rows = rows.data();
    return f;
  }
};

HandFactor hand_factor(const std::vector<int>& parent) {
  const int n = static_cast<int>(parent.size());
  HandFactor h;
  h.dense = Eigen::MatrixXd::Zero(n, n);
  h.pi.push_back(0);
  h.px.push_back(0);
  for (int s = 0; s < n; ++s) {
    h.perm.push_back(s);
    h.super.push_back(s);
    std::vector<int> column{s};
    for (int a = parent[s]; a >= 0 && a < n; a = parent[a]) column.push_back(a);  // the path to the root
    std::sort(column.begin() + 1, column.end());
    for (int r : column) {
      const double v = r == s ? 2.0 + fixtures::uniform() : 0.3 * fixtures::uniform();
      h.rows.push_back(r);
      h.values.push_back(v);
      h.dense(r, s) = v;
    }
    h.pi.push_back(static_cast<int>(h.rows.size()));
    h.px.push_back(static_cast<int>(h.values.size()));
  }
  h.super.push_back(n);
  return h;
}

}  // namespace

TEST(supernodal_solve_splits_the_tree_in_two_and_solves_exactly) {
  // Postorder, root 10: its children 6 (subtree 0..6, heavy) and 9 (7..9); 6's children 2
  // (0..2) and 5 (3..5). The frontier must open 6 to balance the bins.
  const std::vector<int> parent = {2, 2, 6, 5, 5, 6, 10, 9, 9, 10, -1};
  const HandFactor h = hand_factor(parent);
  const SupernodalFactor L = h.view();
  const SupernodalSplit split = SupernodalSplit::of(L);
  CHECK(!split.bins[0].empty() && !split.bins[1].empty());
  CHECK((split.top == std::vector<Index>{6, 10}));  // 6 opened, its subtrees and 9 binned
  Index covered = static_cast<Index>(split.top.size());
  for (const auto& bin : split.bins)
    for (const auto& [first, last] : bin) covered += last - first;
  CHECK(covered == L.nsuper);  // every supernode once
  const Vec b = fixtures::random_matrix<Vec>(L.n, 1);
  Vec x;
  SupernodalWork<double> work;
  supernodal_solve(L, split, h.values.data(), b, x, work);
  const Vec exact = (h.dense * h.dense.transpose()).ldlt().solve(b);
  CHECK((x - exact).norm() <= 1e-13 * exact.norm());
  // Not in postorder (2's subtree {0, 2} is not a range): no split, the same answer.
  const std::vector<int> unordered = {2, 3, 3, -1};
  const HandFactor u = hand_factor(unordered);
  const SupernodalSplit serial = SupernodalSplit::of(u.view());
  CHECK(serial.bins[0].empty() && serial.bins[1].empty() && serial.top.size() == 4);
  supernodal_solve(u.view(), serial, u.values.data(), Vec(Vec::Ones(4)), x, work);
  const Vec exact_u = (u.dense * u.dense.transpose()).ldlt().solve(Vec(Vec::Ones(4)));
  CHECK((x - exact_u).norm() <= 1e-13 * exact_u.norm());
}

TEST(supernodal_solve_is_the_same_on_two_threads) {
  if (!have_openmp()) {
    std::puts("  skipped: needs OpenMP");
    return;
  }
  // 3,087 unknowns: above the two-thread threshold of the sweeps.
  const auto system = fixtures::implicit_system(fixtures::tet_beam(20, 6, 6), Material{1e6, 0.3, 1000.0}, 1e-2);
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> scalar;
  system.A.copy_to(scalar);
  const Vec b = fixtures::random_matrix<Vec>(scalar.rows(), 1);
  for (const auto backend : backends())
    for (bool single : {false, true}) {
      if (backend == SparseCholesky::Backend::Eigen) continue;
      SparseCholesky cholesky(backend);
      cholesky.set_single_precision_solve(single);
      cholesky.analyze(scalar);
      CHECK(cholesky.factorize(scalar));
      const int before = num_threads();
      Vec x1, x2;
      set_num_threads(1);
      cholesky.solve(b, x1);
      set_num_threads(2);
      cholesky.solve(b, x2);
      set_num_threads(before);
      CHECK(x1 == x2);  // to the bit
      const Vec residual = b - scalar * x1;
      CHECK(residual.norm() <= (single ? 1e-4 : 1e-12) * b.norm());
    }
}
