// Shared inputs of the C++ unit tests: seeded random numbers, a structured tet mesh and an
// assembled SPD system A = M + dt^2 K built from the element matrices alone.
#pragma once

#include <random>
#include <vector>

#include "corotate/elements/element_matrices.hpp"
#include "corotate/meshes/structured_box.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"
#include "test_driver.hpp"

namespace fixtures {

using namespace corotate;

inline std::mt19937& rng() {
  static std::mt19937 engine(20240611);
  return engine;
}
// Every test starts from the same seed (test_driver.hpp), whatever ran before it.
inline const bool reseeded_before_each_test = [] {
  ::test_driver::before_each().push_back([] { rng().seed(20240611); });
  return true;
}();

inline double uniform(double lo = -1, double hi = 1) { return std::uniform_real_distribution<double>(lo, hi)(rng()); }

template <class M>
M random_matrix(Index rows = M::RowsAtCompileTime, Index cols = M::ColsAtCompileTime) {
  M m(rows, cols);
  for (Index j = 0; j < m.cols(); ++j)
    for (Index i = 0; i < m.rows(); ++i) m(i, j) = uniform();
  return m;
}

// Proper rotation from a random unit quaternion.
inline Mat3 random_rotation() {
  Eigen::Quaterniond q(uniform(), uniform(), uniform(), uniform());
  q.normalize();
  return q.toRotationMatrix();
}

struct Mesh {
  Nodes points;
  Connectivity cells;
};

// nx x ny x nz unit cubes cut into tets: corotate.beam's mesh (meshes/structured_box.hpp).
inline Mesh tet_beam(int nx, int ny, int nz) {
  StructuredMesh m = structured_box("tet4", {nx, ny, nz}, Vec3(nx, ny, nz));
  return {std::move(m.points), std::move(m.cells)};
}

// The nodes on the plane x = 0 (a beam's clamped end).
inline std::vector<Index> nodes_at_x0(const Mesh& mesh) {
  std::vector<Index> nodes;
  for (Index i = 0; i < mesh.points.cols(); ++i)
    if (mesh.points(0, i) == 0) nodes.push_back(i);
  return nodes;
}

// A = M + dt^2 K of linear elasticity on a tet mesh, assembled block by block; dense copy too.
struct System {
  BlockSparseMatrix A;
  Eigen::MatrixXd dense;
};

inline System implicit_system(const Mesh& mesh, const Material& material, double dt) {
  System s{BlockSparseMatrix::from_cells(mesh.points.cols(), mesh.cells), {}};
  s.A.set_zero();
  for (Index e = 0; e < mesh.cells.rows(); ++e) {
    Eigen::Matrix<double, 3, 4> X;
    for (int a = 0; a < 4; ++a) X.col(a) = mesh.points.col(mesh.cells(e, a));
    const auto em = compute_element_matrices<Tet4>(X, material, e);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        auto block = s.A.block(s.A.block_index(mesh.cells(e, a), mesh.cells(e, b)));
        block += dt * dt * em.stiffness.block<3, 3>(3 * a, 3 * b);
        block.diagonal().array() += em.mass(a, b);
      }
  }
  s.dense = Eigen::MatrixXd::Zero(s.A.num_dofs(), s.A.num_dofs());
  for (Index i = 0; i < s.A.num_nodes(); ++i)
    for (int k = s.A.row_start()[i]; k < s.A.row_start()[i + 1]; ++k)
      s.dense.block<3, 3>(3 * i, 3 * s.A.columns()[k]) = s.A.block(k);
  return s;
}

}  // namespace fixtures
