// Edge-against-edge contact's geometry: the nearest points of two segments against a brute
// force search, and a closed surface's edges with their convexity.
#include <random>

#include "corotate/contact/closest_points_on_segments.hpp"
#include "corotate/contact/surface_edges.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

// The distance of the segments' nearest points by a 401 x 401 grid of (s, t), refined once
// around its best: within ~1e-9 of the true minimum for segments of unit size.
double grid_minimum(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  double best = 1e300, bs = 0, bt = 0;
  auto search = [&](double s0, double s1, double t0, double t1) {
    for (int i = 0; i <= 400; ++i)
      for (int j = 0; j <= 400; ++j) {
        const double s = s0 + (s1 - s0) * i / 400, t = t0 + (t1 - t0) * j / 400;
        const double d2 = (a + s * (b - a) - c - t * (d - c)).squaredNorm();
        if (d2 < best) best = d2, bs = s, bt = t;
      }
  };
  search(0, 1, 0, 1);
  search(std::max(0.0, bs - 0.005), std::min(1.0, bs + 0.005), std::max(0.0, bt - 0.005), std::min(1.0, bt + 0.005));
  return best;
}

// A unit cube's surface: 8 corners, 12 outward triangles (two per face, split by a diagonal).
Triangles cube_triangles() {
  return {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
          {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
}

Nodes cube_corners() {
  Nodes x(3, 8);
  x << 0, 1, 1, 0, 0, 1, 1, 0,  //
      0, 0, 1, 1, 0, 0, 1, 1,   //
      0, 0, 0, 0, 1, 1, 1, 1;
  return x;
}

}  // namespace

TEST(segment_nearest_points_match_a_brute_force_search) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  auto point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  for (int k = 0; k < 200; ++k) {
    const Vec3 a = point(), b = point(), c = point();
    // Every fourth pair parallel, every fifth with a segment shrunk to a point.
    Vec3 d = k % 4 == 0 ? Vec3(c + 0.7 * (b - a)) : point();
    const Vec3 bb = k % 5 == 0 ? a : b;
    const SegmentPoints p = closest_points_on_segments(a, bb, c, d);
    CHECK(p.s >= 0 && p.s <= 1 && p.t >= 0 && p.t <= 1);
    CHECK_NEAR(p.distance2, (a + p.s * (bb - a) - c - p.t * (d - c)).squaredNorm(), 1e-12);
    CHECK_NEAR(std::sqrt(p.distance2), std::sqrt(grid_minimum(a, bb, c, d)), 1e-6);
  }
  // Two crossed segments 0.5 apart: the nearest points are where they cross in plan.
  const SegmentPoints cross =
      closest_points_on_segments(Vec3(-1, 0.2, 0.5), Vec3(1, 0.2, 0.5), Vec3(0.3, -1, 0), Vec3(0.3, 1, 0));
  CHECK_NEAR(cross.s, 0.65, 1e-14);
  CHECK_NEAR(cross.t, 0.6, 1e-14);
  CHECK_NEAR(cross.distance2, 0.25, 1e-14);
}

TEST(a_cube_has_eighteen_edges_of_which_twelve_are_convex) {
  const Triangles triangles = cube_triangles();
  const SurfaceEdges edges = surface_edges(triangles);
  CHECK(edges.size() == 18);
  const Nodes x = cube_corners();
  Nodes normals(3, static_cast<Index>(triangles.size()));
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Vec3 a = x.col(triangles[t][0]);
    normals.col(static_cast<Index>(t)) = (x.col(triangles[t][1]) - a).cross(x.col(triangles[t][2]) - a).normalized();
  }
  int convex = 0;
  for (int e = 0; e < edges.size(); ++e) {
    const auto [from, to] = edges.vertices[e];
    const double length = (x.col(from) - x.col(to)).norm();
    const bool ridge = convex_edge(edges, e, x, normals, 1e-6);
    convex += ridge;
    CHECK(ridge == (std::abs(length - 1) < 1e-12));  // the cube's edges; not its faces' diagonals
    // Each edge runs forward in its first triangle and backward in its second; the opposite
    // corners are the triangles' third vertices.
    for (int k = 0; k < 2; ++k) {
      const auto& t = triangles[edges.faces[e][k]];
      int at = 0;
      while (t[at] != (k == 0 ? from : to)) ++at;
      CHECK(t[(at + 1) % 3] == (k == 0 ? to : from));
      CHECK(t[(at + 2) % 3] == edges.opposite[e][k]);
      CHECK(edges.of_triangle[edges.faces[e][k]][at] == e);
    }
  }
  CHECK(convex == 12);
  // Folding the top face along its diagonal 4-6: raising corner 4 (on the diagonal) makes it
  // a ridge, raising corner 5 (off it) a valley.
  int diagonal = -1;
  for (int e = 0; e < edges.size(); ++e)
    if (std::min(edges.vertices[e][0], edges.vertices[e][1]) == 4 &&
        std::max(edges.vertices[e][0], edges.vertices[e][1]) == 6)
      diagonal = e;
  CHECK(diagonal >= 0);
  for (const int raised : {4, 5}) {
    Nodes folded = x;
    folded(2, raised) += 0.2;
    for (size_t t = 0; t < triangles.size(); ++t) {
      const Vec3 a = folded.col(triangles[t][0]);
      normals.col(static_cast<Index>(t)) =
          (folded.col(triangles[t][1]) - a).cross(folded.col(triangles[t][2]) - a).normalized();
    }
    CHECK(convex_edge(edges, diagonal, folded, normals, 1e-6) == (raised == 4));
  }
}

TEST(surface_edges_refuse_an_open_surface) {
  Triangles open = cube_triangles();
  open.pop_back();  // a hole
  CHECK_THROWS(surface_edges(open), InvalidInput);
  Triangles fin = cube_triangles();
  fin.push_back({0, 1, 2});  // a third triangle on edges of the bottom
  CHECK_THROWS(surface_edges(fin), InvalidInput);
}
