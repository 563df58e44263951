// BlockProlongator: its 3 x 6 block products P c and P^T r equal the scalar sparse ones
// (aggregates with fewer than six coarse DOFs included), on any number of threads.
#include "corotate/parallel.hpp"
#include "corotate/solvers/block_prolongator.hpp"
#include "corotate/solvers/smoothed_aggregation.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

using ScalarMatrix = BlockProlongator::ScalarMatrix;

// A random prolongator of 700 nodes (above the threaded-loop thresholds) and 90 aggregates
// of 6, 3 or 0 coarse DOFs; node i reaches the aggregates i % 90, (i + 7) % 90 and
// (i * 13) % 90, with some entries left out.
ScalarMatrix random_prolongator(std::vector<int>& coarse_start) {
  const int n = 700, m = 90;
  coarse_start.assign(1, 0);
  for (int a = 0; a < m; ++a) coarse_start.push_back(coarse_start.back() + (a % 10 == 3 ? 3 : a % 10 == 5 ? 0 : 6));
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < n; ++i)
    for (int a : {i % m, (i + 7) % m, (i * 13) % m})
      for (int r = 0; r < 3; ++r)
        for (int c = coarse_start[a]; c < coarse_start[a + 1]; ++c)
          if ((i + r + c) % 5 != 0) t.emplace_back(3 * i + r, c, fixtures::uniform());
  ScalarMatrix P(3 * n, coarse_start.back());
  P.setFromTriplets(t.begin(), t.end());
  return P;
}

}  // namespace

TEST(block_prolongator_products_equal_the_scalar_ones) {
  std::vector<int> coarse_start;
  const ScalarMatrix P = random_prolongator(coarse_start);
  BlockProlongator B(P, coarse_start);
  CHECK(B.num_nodes() == 700 && B.num_aggregates() == 90 && B.coarse_size() == P.cols());
  const Vec c = fixtures::random_matrix<Vec>(P.cols(), 1);
  const Vec r = fixtures::random_matrix<Vec>(P.rows(), 1);
  const Vec Pc = P * c, Ptr = P.transpose() * r;
  // P's values are kept in float32 (relative rounding 6e-8; a preconditioner only needs a
  // fixed operator, and P^T and P stay each other's transposes), the sums in double: the
  // error is 6e-8 times the sum of |p||c| over a row's few dozen terms, and not zero.
  const Eigen::SparseMatrix<double, Eigen::RowMajor, int> P_abs = P.cwiseAbs();
  const Vec row_size = P_abs * c.cwiseAbs(), column_size = P_abs.transpose() * r.cwiseAbs();
  Vec y, z = r;
  B.prolong(c, y, false);
  const double prolong_error = ((y - Pc).cwiseAbs().array() / row_size.array()).maxCoeff();
  CHECK(prolong_error < 1.2e-7 && prolong_error > 1e-12);
  B.prolong(c, z, true);
  CHECK(((z - r - y).cwiseAbs().array() <= 1e-13 * (r.cwiseAbs() + row_size).array()).all());  // adds to what is there
  Vec w;
  B.restrict_to(r, w);
  CHECK(w.size() == P.cols());
  CHECK(((w - Ptr).cwiseAbs().array() / column_size.array()).maxCoeff() < 1.2e-7);
}

TEST(block_prolongator_threads_repeat_one_thread_to_the_bit) {
  if (!have_openmp()) {
    std::puts("  skipped: built without OpenMP");
    return;
  }
  std::vector<int> coarse_start;
  BlockProlongator B(random_prolongator(coarse_start), coarse_start);
  const Vec c = fixtures::random_matrix<Vec>(B.coarse_size(), 1);
  const Vec r = fixtures::random_matrix<Vec>(3 * B.num_nodes(), 1);
  Vec y1, y2, w1, w2;
  const int before = num_threads();
  B.prolong(c, y1, false);
  B.restrict_to(r, w1);
  set_num_threads(2);
  B.prolong(c, y2, false);
  B.restrict_to(r, w2);
  set_num_threads(before);
  CHECK(y1 == y2);
  CHECK(w1 == w2);
}

TEST(block_prolongator_rejects_columns_outside_its_aggregates) {
  std::vector<int> coarse_start;
  const ScalarMatrix P = random_prolongator(coarse_start);
  std::vector<int> short_start(coarse_start.begin(), coarse_start.end() - 1);
  CHECK_THROWS(BlockProlongator(P, short_start), InvalidInput);
  std::vector<int> wide = {0, 7, int(P.cols())};  // an aggregate of 7 DOFs
  CHECK_THROWS(BlockProlongator(P, wide), InvalidInput);
  CHECK_THROWS(BlockProlongator(ScalarMatrix(10, 6), {0, 6}), InvalidInput);  // 10 rows: not 3 per node
}

TEST(smoothed_aggregation_blocks_equal_the_scalar_products) {
  // P = T - w D^-1 A T and P^T A P from 3 x 6 blocks equal the scalar sparse products, on a
  // beam's implicit system with the x = 0 face's DOFs decoupled (fixed) and aggregates of 6,
  // 3 and 0 coarse DOFs (T's columns beyond an aggregate's rank zero).
  const fixtures::Mesh mesh = fixtures::tet_beam(6, 2, 2);
  auto system = fixtures::implicit_system(mesh, Material{1e6, 0.3, 1000.0}, 0.01);
  BlockSparseMatrix& A = system.A;
  const Index n = A.num_nodes();
  for (Index i = 0; i < n; ++i) {  // fixed: the row and column of node i, identity on the diagonal
    if (mesh.points(0, i) > 1e-9) continue;
    for (int e = A.row_start()[i]; e < A.row_start()[i + 1]; ++e) {
      const Index j = A.columns()[e];
      A.block(e).setZero();
      A.block(A.block_index(j, i)).setZero();
    }
    A.block(A.diagonal_block(i)).setIdentity();
  }
  const int m = 11;
  std::vector<int> aggregate(n), coarse_start(1, 0);
  for (Index i = 0; i < n; ++i) aggregate[i] = static_cast<int>((i * 7) % m);
  for (int a = 0; a < m; ++a) coarse_start.push_back(coarse_start.back() + (a == 3 ? 3 : a == 5 ? 0 : 6));
  Block36List tentative(n, Block36::Zero());
  std::vector<Eigen::Triplet<double, int>> t;
  for (Index i = 0; i < n; ++i) {
    const int a = aggregate[i], rank = coarse_start[a + 1] - coarse_start[a];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < rank; ++c)
        if (mesh.points(0, i) > 1e-9) {
          tentative[i](r, c) = fixtures::uniform();
          t.emplace_back(3 * i + r, coarse_start[a] + c, tentative[i](r, c));
        }
  }
  using Sparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  Sparse T(3 * n, coarse_start.back()), Dinv(3 * n, 3 * n), S(3 * n, 3 * n);
  T.setFromTriplets(t.begin(), t.end());
  std::vector<Mat3> inverse_diagonal(n);
  t.clear();
  std::vector<Eigen::Triplet<double, int>> s;
  for (Index i = 0; i < n; ++i) {
    inverse_diagonal[i] = Mat3(A.block(A.diagonal_block(i))).inverse();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) t.emplace_back(3 * i + r, 3 * i + c, inverse_diagonal[i](r, c));
    for (int e = A.row_start()[i]; e < A.row_start()[i + 1]; ++e)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) s.emplace_back(3 * i + r, 3 * A.columns()[e] + c, A.block(e)(r, c));
  }
  Dinv.setFromTriplets(t.begin(), t.end());
  S.setFromTriplets(s.begin(), s.end());
  const double w = 0.3;
  const Sparse P_scalar = T - w * (Dinv * (S * T));
  const Eigen::MatrixXd C_scalar = Eigen::MatrixXd(P_scalar.transpose() * (S * P_scalar));

  const NodeAggregateBlocks P = smoothed_prolongator(A, inverse_diagonal, aggregate, tentative, m, w);
  Eigen::MatrixXd P_dense = Eigen::MatrixXd::Zero(3 * n, coarse_start.back());
  for (Index i = 0; i < n; ++i) {
    CHECK(std::is_sorted(P.aggregate.begin() + P.start[i], P.aggregate.begin() + P.start[i + 1]));
    for (int k = P.start[i]; k < P.start[i + 1]; ++k) {
      const int a = P.aggregate[k];
      P_dense.block(3 * i, coarse_start[a], 3, coarse_start[a + 1] - coarse_start[a]) =
          P.blocks[k].leftCols(coarse_start[a + 1] - coarse_start[a]);
    }
    if (mesh.points(0, i) <= 1e-9) CHECK(P.start[i + 1] == P.start[i]);  // a fixed node: no blocks
  }
  CHECK((P_dense - Eigen::MatrixXd(P_scalar)).cwiseAbs().maxCoeff() <= 1e-12 * P_dense.cwiseAbs().maxCoeff());
  const Eigen::MatrixXd C = Eigen::MatrixXd(galerkin_product(A, P, coarse_start));
  CHECK(C.rows() == coarse_start.back());
  CHECK((C - C.transpose()).cwiseAbs().maxCoeff() == 0.0);  // exactly symmetric
  CHECK((C - C_scalar).cwiseAbs().maxCoeff() <= 1e-12 * C_scalar.cwiseAbs().maxCoeff());
  // The prolongator built from the blocks is the one built from the scalar matrix.
  BlockProlongator from_blocks(P, coarse_start), from_scalar(P_scalar, coarse_start);
  const Vec c = fixtures::random_matrix<Vec>(coarse_start.back(), 1);
  Vec y1, y2;
  from_blocks.prolong(c, y1, false);
  from_scalar.prolong(c, y2, false);
  CHECK(y1 == y2);
}
