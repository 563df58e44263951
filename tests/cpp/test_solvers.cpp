// Linear solvers on A = M + dt^2 K of a small elastic tet beam (SPD, condition number ~1e3):
// PCG reaches its tolerance with every preconditioner, the direct solver solves to round-off.
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"
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

TEST(pcg_rejects_bad_settings) {
  CHECK_THROWS(PCG(PCGSettings{0, 1e-6, true, PreconditionerKind::Jacobi}), InvalidInput);
  CHECK_THROWS(PCG(PCGSettings{10, 0.0, true, PreconditionerKind::Jacobi}), InvalidInput);
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
