// The direct solver's two backends, SuiteSparse CHOLMOD (when the build found it) and Eigen's
// SimplicialLDLT, solve the same systems to round-off (CHOLMOD's supernodal factor through
// our own triangular sweeps), and both refuse an indefinite one; Auto picks by size.
#include <cstdio>

#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"
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
