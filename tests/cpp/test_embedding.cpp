// Surface embedding: the inverse isoparametric map, the grid search against brute force, the
// exactness of embedded positions under linear fields, and bad input.
#include "corotate/embedding/element_search_grid.hpp"
#include "corotate/embedding/local_coordinates.hpp"
#include "corotate/embedding/surface_embedding.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;
using fixtures::uniform;

namespace {

// A Hex20 with curved edges: the reference cube's nodes, stretched and with each node pushed
// by a smooth bend, so the isoparametric map is genuinely nonlinear.
ElementNodes<Hex20> curved_hex20() {
  ElementNodes<Hex20> X;
  for (int a = 0; a < 20; ++a) {
    const Vec3 s = Hex20::node(a);
    X.col(a) =
        Vec3(2 * s.x(), s.y(), 0.5 * s.z()) + Vec3(0.1 * s.y() * s.y(), 0.15 * s.x() * s.x(), 0.1 * s.x() * s.y());
  }
  return X;
}

Nodes random_points_in_box(Index n, const Vec3& lo, const Vec3& hi) {
  Nodes p(3, n);
  for (Index j = 0; j < n; ++j)
    for (int d = 0; d < 3; ++d) p(d, j) = uniform(lo(d), hi(d));
  return p;
}

}  // namespace

TEST(hex20_inverse_map_recovers_natural_coordinates) {
  const ElementInverseMap<Hex20> map(curved_hex20());
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 xi(uniform(), uniform(), uniform());
    const PointInElement<Hex20> r = map.locate(map.X * Hex20::shape(xi));
    CHECK((r.xi - xi).cwiseAbs().maxCoeff() < 1e-12);
    CHECK(r.criterion == 0.0);
  }
  const Vec3 outside(1.2, 0.0, -1.1);  // natural coordinates outside the cube: excess 0.3
  const PointInElement<Hex20> r = map.locate(map.X * Hex20::shape(outside));
  CHECK_NEAR(r.criterion, 0.3, 1e-12);
}

TEST(tet4_barycentric_criterion_is_paper_sum_of_absolute_coordinates) {
  ElementNodes<Tet4> X;
  X << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const ElementInverseMap<Tet4> map(X);
  const PointInElement<Tet4> inside = map.locate(Vec3(0.2, 0.3, 0.1));
  CHECK_NEAR(inside.criterion, 0.0, 1e-15);
  CHECK_NEAR(inside.weights(0), 0.4, 1e-15);
  const PointInElement<Tet4> out = map.locate(Vec3(-0.25, 0.5, 0.25));  // N = (0.5, -0.25, 0.5, 0.25)
  CHECK_NEAR(out.criterion, 0.5, 1e-15);  // sum |N| - 1 = 1.5 - 1
}

TEST(grid_finds_the_containing_tet_like_brute_force) {
  const fixtures::Mesh mesh = fixtures::tet_beam(6, 3, 2);
  const Nodes p = random_points_in_box(2000, Vec3(0, 0, 0), Vec3(6, 3, 2));
  const SurfaceEmbedding s("tetra", mesh.points, mesh.cells, p, Connectivity(0, 3));
  CHECK(s.report().outside == 0);
  int wrong = 0;
  for (Index v = 0; v < p.cols(); ++v) {
    ElementNodes<Tet4> X;
    for (int a = 0; a < 4; ++a) X.col(a) = mesh.points.col(mesh.cells(s.elements()[v], a));
    if (ElementInverseMap<Tet4>(X).locate(p.col(v)).criterion > 1e-10) ++wrong;
  }
  CHECK(wrong == 0);
}

TEST(embedded_points_follow_a_linear_field_exactly) {
  const fixtures::Mesh mesh = fixtures::tet_beam(4, 2, 2);
  const Nodes p = random_points_in_box(500, Vec3(-0.1, 0, 0), Vec3(4, 2, 2.1));  // some just outside
  const SurfaceEmbedding s("tetra", mesh.points, mesh.cells, p, Connectivity(0, 3));
  CHECK(s.report().outside > 0);
  const Mat3 A = Mat3::Identity() + 0.3 * fixtures::random_matrix<Mat3>();
  const Vec3 b(1, -2, 0.5);
  const Nodes x = (A * mesh.points).colwise() + b;
  Nodes y(3, p.cols());
  s.embed(x, y);
  const Nodes expected = (A * p).colwise() + b;
  CHECK((y - expected).cwiseAbs().maxCoeff() < 1e-13);
}

TEST(vertex_outside_the_body_gets_the_minimum_criterion_and_a_distance) {
  const fixtures::Mesh mesh = fixtures::tet_beam(2, 1, 1);
  Nodes p(3, 1);
  p.col(0) = Vec3(1.0, 0.5, 1.2);  // 0.2 above the top face
  const SurfaceEmbedding s("tetra", mesh.points, mesh.cells, p, Connectivity(0, 3));
  CHECK(s.report().outside == 1);
  CHECK(s.report().farthest_vertex == 0);
  // Brute force: no element has a smaller criterion than the chosen one.
  double best = 1e300;
  for (Index e = 0; e < mesh.cells.rows(); ++e) {
    ElementNodes<Tet4> X;
    for (int a = 0; a < 4; ++a) X.col(a) = mesh.points.col(mesh.cells(e, a));
    best = std::min(best, ElementInverseMap<Tet4>(X).locate(p.col(0)).criterion);
  }
  ElementNodes<Tet4> X;
  for (int a = 0; a < 4; ++a) X.col(a) = mesh.points.col(mesh.cells(s.elements()[0], a));
  CHECK_NEAR(ElementInverseMap<Tet4>(X).locate(p.col(0)).criterion, best, 1e-14);
  CHECK(s.report().max_outside_distance >= 0.2 - 1e-12);  // at least the true distance / size 1
}

TEST(embedding_rejects_bad_input_by_name) {
  const fixtures::Mesh mesh = fixtures::tet_beam(1, 1, 1);
  Nodes p(3, 1);
  p.col(0) = Vec3(0.5, 0.5, 0.5);
  Connectivity tri(1, 3);
  tri << 0, 0, 1;  // vertex 1 does not exist
  CHECK_THROWS(SurfaceEmbedding("tetra", mesh.points, mesh.cells, p, tri), InvalidInput);
  CHECK_THROWS(SurfaceEmbedding("tetra", mesh.points, mesh.cells, Nodes(3, 0), Connectivity(0, 3)), InvalidInput);
  CHECK_THROWS(SurfaceEmbedding("wedge", mesh.points, mesh.cells, p, Connectivity(0, 3)), InvalidInput);
  Nodes far = p;
  far(0, 0) = 50;
  CHECK_THROWS(SurfaceEmbedding("tetra", mesh.points, mesh.cells, far, Connectivity(0, 3)), InvalidInput);
  Nodes nan = p;
  nan(1, 0) = std::nan("");
  CHECK_THROWS(SurfaceEmbedding("tetra", mesh.points, mesh.cells, nan, Connectivity(0, 3)), InvalidInput);
  const SurfaceEmbedding s("tetra", mesh.points, mesh.cells, p, Connectivity(0, 3));
  Nodes out(3, 1), wrong(3, 2);
  CHECK_THROWS(s.embed(Nodes(mesh.points.leftCols(3)), out), InvalidInput);
  CHECK_THROWS(s.embed(mesh.points, wrong), InvalidInput);
}
