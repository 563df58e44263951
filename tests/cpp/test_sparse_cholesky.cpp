// The direct solver's two backends, SuiteSparse CHOLMOD (when the build found it) and Eigen's
// SimplicialLDLT, solve the same systems to round-off (CHOLMOD's supernodal factor through
// our own triangular sweeps), and both refuse an indefinite one; Auto picks by size.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "corotate/parallel.hpp"
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"
#include "corotate/solvers/supernodal_solve.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

TEST(auto_takes_cholmod_for_large_systems_only) {
  // Below kCholmodFromDofs CHOLMOD's supernodes are too small for BLAS to pay (see
  // sparse_cholesky.hpp): Eigen's SimplicialLDLT factorizes faster.
  for (const Index n : {Index(300), SparseCholesky::kCholmodFromDofs}) {
    SparseCholesky::Matrix identity(n, n);
    identity.setIdentity();
    SparseCholesky automatic;
    CHECK(std::string(automatic.backend_name()) == "auto");
    automatic.analyze(identity);
    const bool large = n >= SparseCholesky::kCholmodFromDofs && SparseCholesky::have_cholmod();
    CHECK(std::string(automatic.backend_name()) == (large ? "cholmod" : "eigen"));
    CHECK(automatic.factorize(identity));
    Vec x;
    automatic.solve(Vec::Ones(n), x);
    CHECK((x - Vec::Ones(n)).norm() == 0.0);
  }
}

TEST(cholmod_and_eigen_direct_solves_agree) {
  if (!SparseCholesky::have_cholmod()) {
    std::puts("  skipped: corotate was built without SuiteSparse CHOLMOD (apt-get install libsuitesparse-dev)");
    CHECK_THROWS(SparseCholesky(SparseCholesky::Backend::Cholmod), InvalidInput);
    return;
  }
  // A = M + dt^2 K of a 6 x 3 x 3 tet beam (no fixed nodes: M makes it definite).
  const auto system = fixtures::implicit_system(fixtures::tet_beam(6, 3, 3), Material{1e6, 0.3, 1000.0}, 1e-2);
  const Index n = system.A.num_dofs();
  Vec b(n);
  for (Index i = 0; i < n; ++i) b[i] = fixtures::uniform();
  DirectSolver cholmod(SparseCholesky::Backend::Cholmod), eigen(SparseCholesky::Backend::Eigen);
  CHECK(std::string(cholmod.backend_name()) == "cholmod" && std::string(eigen.backend_name()) == "eigen");
  Vec x_cholmod, x_eigen;
  for (int round = 0; round < 2; ++round) {  // the second reuses the symbolic analysis
    const SolveStats s1 = cholmod.solve(system.A, b, x_cholmod);
    const SolveStats s2 = eigen.solve(system.A, b, x_eigen);
    CHECK(s1.relative_residual < 1e-13 && s2.relative_residual < 1e-13);
    CHECK((x_cholmod - x_eigen).norm() <= 1e-12 * x_eigen.norm());
    // and against the dense solve of the same matrix
    const Vec dense = system.dense.ldlt().solve(b);
    CHECK((x_cholmod - dense).norm() <= 1e-12 * dense.norm());
    b *= -2.0;
  }
  // The single-precision solve of the same factor (a preconditioner's): float round-off
  // times the condition number (~1e3 here), and really float.
  {
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> scalar;
    system.A.copy_to(scalar);
    SparseCholesky single(SparseCholesky::Backend::Cholmod);
    single.set_single_precision_solve(true);
    single.analyze(scalar);
    CHECK(single.factorize(scalar));
    Vec x_single;
    single.solve(b, x_single);
    const Vec dense = system.dense.ldlt().solve(b);
    const double error = (x_single - dense).norm() / dense.norm();
    CHECK(error < 1e-4 && error > 1e-12);
  }
  // An empty system (a two-level coarse space with every DOF fixed) is solved, not a crash.
  SparseCholesky empty(SparseCholesky::Backend::Cholmod);
  const SparseCholesky::Matrix none(0, 0);
  empty.analyze(none);
  CHECK(empty.factorize(none));
  Vec x_none;
  empty.solve(Vec(0), x_none);
  CHECK(x_none.size() == 0);
  // An indefinite matrix: both refuse it.
  BlockSparseMatrix indefinite = system.A;
  indefinite.block(indefinite.diagonal_block(3))(0, 0) = -1e9;
  CHECK_THROWS(cholmod.solve(indefinite, b, x_cholmod), NotPositiveDefinite);
  CHECK_THROWS(eigen.solve(indefinite, b, x_eigen), NotPositiveDefinite);
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

TEST(cholmod_solve_is_the_same_on_two_threads) {
  if (!SparseCholesky::have_cholmod() || !have_openmp()) {
    std::puts("  skipped: needs CHOLMOD and OpenMP");
    return;
  }
  // 3,087 unknowns: above the two-thread threshold of the sweeps.
  const auto system = fixtures::implicit_system(fixtures::tet_beam(20, 6, 6), Material{1e6, 0.3, 1000.0}, 1e-2);
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> scalar;
  system.A.copy_to(scalar);
  const Vec b = fixtures::random_matrix<Vec>(scalar.rows(), 1);
  for (bool single : {false, true}) {
    SparseCholesky cholesky(SparseCholesky::Backend::Cholmod);
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
