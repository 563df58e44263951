// BlockSparseMatrix: the pattern built from cells, and y = A x against a dense product.
#include <set>

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
