// BlockProlongator: its 3 x 6 block products P c and P^T r equal the scalar sparse ones
// (aggregates with fewer than six coarse DOFs included), on any number of threads.
#include "corotate/parallel.hpp"
#include "corotate/solvers/block_prolongator.hpp"
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
