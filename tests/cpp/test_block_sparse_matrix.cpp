// BlockSparseMatrix: the pattern built from cells, and y = A x against a dense product.
#include <algorithm>
#include <array>
#include <set>

#include "corotate/parallel.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

// Two tets sharing the face (1, 2, 3): nodes 0 and 4 are not coupled.
Connectivity two_tets() {
  Connectivity cells(2, 4);
  cells << 0, 1, 2, 3, 1, 2, 3, 4;
  return cells;
}

Eigen::MatrixXd to_dense(const BlockSparseMatrix& A) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(A.num_dofs(), A.num_dofs());
  for (Index i = 0; i < A.num_nodes(); ++i)
    for (int k = A.row_start()[i]; k < A.row_start()[i + 1]; ++k) D.block<3, 3>(3 * i, 3 * A.columns()[k]) = A.block(k);
  return D;
}

}  // namespace

TEST(pattern_from_cells_couples_exactly_the_nodes_that_share_a_cell) {
  const BlockSparseMatrix A = BlockSparseMatrix::from_cells(5, two_tets());
  CHECK(A.num_nodes() == 5);
  CHECK(A.num_dofs() == 15);
  // 5 diagonal blocks + 2 x 9 coupled pairs (6 per tet, 3 of them shared).
  CHECK(A.num_blocks() == 23);
  CHECK(A.values().size() == 9 * 23u);
  const Connectivity cells = two_tets();
  std::set<std::pair<int, int>> coupled;
  for (Index e = 0; e < cells.rows(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) coupled.insert({cells(e, a), cells(e, b)});
  for (int i = 0; i < 5; ++i) {
    for (int k = A.row_start()[i] + 1; k < A.row_start()[i + 1]; ++k) CHECK(A.columns()[k - 1] < A.columns()[k]);
    CHECK(A.diagonal_block(i) == A.block_index(i, i));
    for (int j = 0; j < 5; ++j) {
      const int k = A.block_index(i, j);
      CHECK((k >= 0) == (coupled.count({i, j}) == 1));
      if (k >= 0) CHECK(A.columns()[k] == j);
    }
  }
  CHECK(A.block_index(0, 4) == -1);
  CHECK(A.block_index(4, 0) == -1);
}

TEST(pattern_from_pairs_always_has_the_diagonal) {
  const BlockSparseMatrix A = BlockSparseMatrix::from_pairs(4, {{0, 2}, {2, 0}, {1, 3}});
  CHECK(A.num_blocks() == 4 + 4);  // duplicates merged, both triangles stored
  for (int i = 0; i < 4; ++i) CHECK(A.diagonal_block(i) >= 0);
  CHECK(A.block_index(0, 2) >= 0 && A.block_index(2, 0) >= 0);
  CHECK(A.block_index(0, 1) == -1);
}

TEST(multiply_equals_the_dense_product) {
  const fixtures::Mesh mesh = fixtures::tet_beam(3, 2, 2);
  BlockSparseMatrix A = BlockSparseMatrix::from_cells(mesh.points.cols(), mesh.cells);
  for (double& v : A.values()) v = fixtures::uniform();  // any values, not only symmetric ones
  const Eigen::MatrixXd D = to_dense(A);
  const Vec x = fixtures::random_matrix<Vec>(A.num_dofs(), 1);
  Vec y(A.num_dofs());
  A.multiply(x, y);
  const Vec expected = D * x;
  // Same products summed in a different order: round-off of n terms of size |a||x|.
  const double bound = 1e-15 * A.num_dofs() * (D.cwiseAbs() * x.cwiseAbs()).maxCoeff();
  CHECK_NEAR((y - expected).cwiseAbs().maxCoeff(), 0.0, bound);

  BlockSparseMatrix B = A;
  B.assign_scaled(-2.5, A);
  B.multiply(x, y);
  CHECK_NEAR((y + 2.5 * expected).cwiseAbs().maxCoeff(), 0.0, 2.5 * bound);
  B.set_zero();
  B.multiply(x, y);
  CHECK(y.isZero(0.0));
}

TEST(copy_to_gives_the_same_scalar_matrix) {
  const fixtures::Mesh mesh = fixtures::tet_beam(2, 1, 1);
  BlockSparseMatrix A = BlockSparseMatrix::from_cells(mesh.points.cols(), mesh.cells);
  for (double& v : A.values()) v = fixtures::uniform();
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> S;
  A.copy_to(S);
  const Eigen::MatrixXd D = to_dense(A);
  // Both triangles are stored, so the CSR copy read as CSC is the transpose.
  CHECK(Eigen::MatrixXd(S) == D.transpose());
  CHECK(S.nonZeros() == static_cast<Index>(A.values().size()));
  for (double& v : A.values()) v *= 3;  // second call: values only
  A.copy_to(S);
  CHECK(Eigen::MatrixXd(S) == 3 * D.transpose());
}

namespace {

// A random exactly symmetric matrix on a tet beam's pattern.
BlockSparseMatrix random_symmetric(int nx, int ny, int nz) {
  const fixtures::Mesh mesh = fixtures::tet_beam(nx, ny, nz);
  BlockSparseMatrix A = BlockSparseMatrix::from_cells(mesh.points.cols(), mesh.cells);
  for (Index i = 0; i < A.num_nodes(); ++i)
    for (int k = A.row_start()[i]; k < A.row_start()[i + 1]; ++k) {
      const int j = A.columns()[k];
      if (j < i) continue;
      Mat3 b = fixtures::random_matrix<Mat3>();
      if (j == i) b = (b + b.transpose()).eval();
      A.block(k) = b;
      A.block(A.block_index(j, i)) = b.transpose();
    }
  return A;
}

}  // namespace

TEST(symmetric_multiply_equals_the_full_one) {
  // One chunk (48 nodes) and several (31 x 7 x 7 = 1,519 nodes: 2 chunks; 3,321: 6).
  for (const auto& dims : {std::array<int, 3>{3, 2, 2}, {30, 6, 6}, {40, 8, 8}}) {
    const BlockSparseMatrix A = random_symmetric(dims[0], dims[1], dims[2]);
    CHECK(A.is_symmetric());
    CHECK(A.num_chunks() == std::clamp<Index>(A.num_nodes() / 512, 1, 8));
    const Vec x = fixtures::random_matrix<Vec>(A.num_dofs(), 1);
    Vec full(A.num_dofs()), sym = Vec::Constant(A.num_dofs(), 7.0);  // overwritten, not added to
    A.multiply(x, full);
    A.multiply_symmetric(x, sym);
    // The same ~45 products per entry, summed in another order.
    CHECK_NEAR((sym - full).cwiseAbs().maxCoeff(), 0.0, 1e-13);
    CHECK(full.cwiseAbs().maxCoeff() > 1);
    if (have_openmp()) {
      const int before = num_threads();
      for (int threads : {2, 3}) {
        set_num_threads(threads);
        Vec threaded(A.num_dofs());
        A.multiply_symmetric(x, threaded);
        CHECK(threaded == sym);  // to the bit
      }
      set_num_threads(before);
    }
  }
}

TEST(is_symmetric_sees_one_changed_entry) {
  BlockSparseMatrix A = random_symmetric(3, 2, 2);
  CHECK(A.is_symmetric());
  const int k = A.block_index(0, 1);
  A.block(k)(2, 1) += 1e-15;
  CHECK(!A.is_symmetric());
  CHECK(A.is_symmetric(1e-14));  // within 1e-14 of the largest entry (~1)
  A.block(k)(2, 1) += 1e-3;
  CHECK(!A.is_symmetric(1e-12));
}

TEST(single_precision_product_is_the_double_one_to_float_rounding) {
  for (const auto& dims : {std::array<int, 3>{3, 2, 2}, {30, 6, 6}, {40, 8, 8}}) {
    const BlockSparseMatrix A = random_symmetric(dims[0], dims[1], dims[2]);
    const Vec x = fixtures::random_matrix<Vec>(A.num_dofs(), 1);
    Vec exact(A.num_dofs()), single = Vec::Constant(A.num_dofs(), 7.0);  // overwritten
    A.multiply(x, exact);
    SinglePrecisionSymmetric S;
    S.assign(A);
    S.multiply(x, single);
    // Each value rounded once to float (relative 6e-8), the sums in double: the error is
    // about 6e-8 times the sum of |a||x| over a row's ~45 terms, and it is not zero (the copy
    // really is float).
    const Vec magnitude = to_dense(A).cwiseAbs() * x.cwiseAbs();
    const double error = ((single - exact).cwiseAbs().array() / magnitude.array()).maxCoeff();
    CHECK(error < 1.2e-7);
    CHECK(error > 1e-10);
    if (have_openmp()) {
      const int before = num_threads();
      set_num_threads(2);
      Vec threaded(A.num_dofs());
      S.multiply(x, threaded);
      CHECK(threaded == single);  // the same row chunks: to the bit
      set_num_threads(before);
    }
  }
}

TEST(single_precision_copy_scales_matrices_beyond_float_range_and_follows_reassignment) {
  BlockSparseMatrix A = random_symmetric(3, 2, 2);
  const Vec x = fixtures::random_matrix<Vec>(A.num_dofs(), 1);
  Vec exact(A.num_dofs()), single(A.num_dofs());
  SinglePrecisionSymmetric S;
  // 1e-300 and 1e300 are far outside float's range (1e-38 to 3e38): unscaled, the copy
  // would be all zeros or all infinities.
  for (double scale : {1e-300, 1.0, 1e300}) {
    BlockSparseMatrix B = A;
    B.assign_scaled(scale, A);
    B.multiply(x, exact);
    S.assign(B);
    S.multiply(x, single);
    CHECK(single.allFinite());
    CHECK((single - exact).norm() <= 1e-6 * exact.norm());
  }
  // A matrix of another pattern gets a layout of its own.
  const BlockSparseMatrix C = random_symmetric(4, 2, 2);
  const Vec xc = fixtures::random_matrix<Vec>(C.num_dofs(), 1);
  Vec exact_c(C.num_dofs()), single_c(C.num_dofs());
  C.multiply(xc, exact_c);
  S.assign(C);
  CHECK(S.num_nodes() == C.num_nodes());
  S.multiply(xc, single_c);
  CHECK((single_c - exact_c).norm() <= 1e-6 * exact_c.norm());
}
