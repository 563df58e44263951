#include "corotate/contact/triangle_mesh.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>

#include "corotate/contact/closest_point_on_triangle.hpp"
#include "corotate/contact/surface_edges.hpp"

namespace corotate {

struct TriangleMesh::Geometry {
  Nodes vertices, velocities;
  std::shared_ptr<const Triangles> triangles;
  // The triangle across edge k of triangle t (edge k joins corners k and k + 1): 3 t + k.
  std::shared_ptr<const std::vector<int>> edge_neighbours;
  std::vector<Vec3> face_normals;    // unit; zero for a zero-area face
  std::vector<Vec3> vertex_normals;  // angle-weighted pseudonormals, unit
  TriangleBvh bvh;
};

struct TriangleMesh::Nearest {
  int triangle = -1;
  TrianglePoint at;
};

namespace {

double diagonal(const Nodes& vertices) {
  return (vertices.rowwise().maxCoeff() - vertices.rowwise().minCoeff()).norm();
}

// Checks that every edge joins exactly two triangles in opposite directions and returns, per
// triangle edge, the triangle on its other side.
std::vector<int> edge_neighbours(const Triangles& triangles) {
  const SurfaceEdges edges = surface_edges(triangles, "the obstacle mesh");
  std::vector<int> neighbours(3 * triangles.size(), -1);
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const auto& faces = edges.faces[edges.of_triangle[t][k]];
      neighbours[3 * t + k] = faces[0] == static_cast<int>(t) ? faces[1] : faces[0];
    }
  return neighbours;
}

}  // namespace

namespace {

// The face normals and the angle-weighted vertex normals of `vertices` into storage of the
// right sizes (no allocation).
void compute_normals(const Nodes& vertices, const Triangles& tris, std::vector<Vec3>& face_normals,
                     std::vector<Vec3>& vertex_normals) {
  std::fill(vertex_normals.begin(), vertex_normals.end(), Vec3::Zero());
  for (size_t t = 0; t < tris.size(); ++t) {
    const Vec3 n = (vertices.col(tris[t][1]) - vertices.col(tris[t][0]))
                       .cross(vertices.col(tris[t][2]) - vertices.col(tris[t][0]));
    const double length = n.norm();
    face_normals[t] = length > 0 ? Vec3(n / length) : Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = vertices.col(tris[t][(k + 1) % 3]) - vertices.col(tris[t][k]);
      const Vec3 e2 = vertices.col(tris[t][(k + 2) % 3]) - vertices.col(tris[t][k]);
      vertex_normals[tris[t][k]] += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * face_normals[t];
    }
  }
  for (Vec3& n : vertex_normals)
    if (n.norm() > 0) n.normalize();
}

}  // namespace

std::shared_ptr<TriangleMesh::Geometry> TriangleMesh::make_geometry(
    const Nodes& vertices, const Nodes& velocities, std::shared_ptr<const Triangles> triangles,
    std::shared_ptr<const std::vector<int>> edge_neighbours, const TriangleBvh* bvh) {
  auto g = std::make_shared<Geometry>();
  g->vertices = vertices;
  g->velocities = velocities;
  g->triangles = std::move(triangles);
  g->edge_neighbours = std::move(edge_neighbours);
  const Triangles& tris = *g->triangles;
  g->face_normals.resize(tris.size());
  g->vertex_normals.resize(vertices.cols());
  compute_normals(vertices, tris, g->face_normals, g->vertex_normals);
  if (bvh) {
    g->bvh = *bvh;
    g->bvh.refit(vertices, tris);
  } else {
    g->bvh = TriangleBvh(vertices, tris);
  }
  return g;
}

void TriangleMesh::move_owned_vertices(const Nodes& vertices, const Nodes& velocities) {
  // geometry_ was made non-const (make_geometry) and no other thread reads this mesh.
  Geometry& g = const_cast<Geometry&>(*geometry_);
  if (vertices.cols() != g.vertices.cols() || velocities.cols() != g.vertices.cols())
    throw InvalidInput("the surface mesh has " + std::to_string(g.vertices.cols()) + " vertices, not " +
                       std::to_string(vertices.cols()));
  g.vertices = vertices;
  g.velocities = velocities;
  compute_normals(g.vertices, *g.triangles, g.face_normals, g.vertex_normals);
  g.bvh.refit(g.vertices, *g.triangles);
}

TriangleMesh::TriangleMesh(const Nodes& vertices, const Triangles& input) {
  const Index n = vertices.cols();
  for (Index i = 0; i < n; ++i)
    if (!vertices.col(i).allFinite())
      throw InvalidInput("vertex " + std::to_string(i) + " of the obstacle mesh is not finite");
  if (input.size() < 4)
    throw InvalidInput("a closed triangle mesh needs at least 4 triangles, got " + std::to_string(input.size()));
  const double scale = diagonal(vertices);
  for (size_t t = 0; t < input.size(); ++t) {
    for (int k = 0; k < 3; ++k)
      if (input[t][k] < 0 || input[t][k] >= n) {
        std::ostringstream msg;
        msg << "triangle " << t << " of the obstacle mesh refers to vertex " << input[t][k] << "; the mesh has " << n
            << " vertices";
        throw InvalidInput(msg.str());
      }
    const Vec3 a = vertices.col(input[t][0]), b = vertices.col(input[t][1]), c = vertices.col(input[t][2]);
    if ((b - a).cross(c - a).norm() <= 1e-12 * scale * scale)
      throw InvalidInput("triangle " + std::to_string(t) + " of the obstacle mesh has zero area");
  }
  auto neighbours = edge_neighbours(input);
  double volume = 0;
  for (const auto& t : input) volume += vertices.col(t[0]).dot(vertices.col(t[1]).cross(vertices.col(t[2]))) / 6;
  if (std::abs(volume) <= 1e-12 * scale * scale * scale) throw InvalidInput("the obstacle mesh encloses no volume");
  auto triangles = std::make_shared<Triangles>(input);
  if (volume < 0) {  // wound inward: reverse every triangle (a, b, c) -> (a, c, b)
    for (size_t t = 0; t < triangles->size(); ++t) {
      std::swap((*triangles)[t][1], (*triangles)[t][2]);
      std::swap(neighbours[3 * t], neighbours[3 * t + 2]);  // edge ab <-> edge ca (bc stays)
    }
  }
  geometry_ = make_geometry(vertices, Nodes::Zero(3, n), std::move(triangles),
                            std::make_shared<const std::vector<int>>(std::move(neighbours)), nullptr);
}

std::shared_ptr<const TriangleMesh::Geometry> TriangleMesh::geometry() const { return std::atomic_load(&geometry_); }

namespace {

template <class Geometry>
TrianglePoint nearest_point(const Geometry& g, const Vec3& p, int& triangle) {
  const Triangles& tris = *g.triangles;
  TrianglePoint best{};
  double best2 = std::numeric_limits<double>::infinity();
  triangle = -1;
  g.bvh.nearest(p, best2, [&](int t) {
    const TrianglePoint q = closest_point_on_triangle(p, g.vertices.col(tris[t][0]), g.vertices.col(tris[t][1]),
                                                      g.vertices.col(tris[t][2]));
    const double d2 = (p - q.point).squaredNorm();
    if (d2 < best2) {
      best2 = d2;
      best = q;
      triangle = t;
    }
    return best2;
  });
  return best;
}

template <class Geometry>
Vec3 pseudonormal(const Geometry& g, int t, TriangleFeature feature) {
  const auto& tri = (*g.triangles)[t];
  const auto edge = [&](int k) {
    const Vec3 sum = g.face_normals[t] + g.face_normals[(*g.edge_neighbours)[3 * t + k]];
    return sum.norm() > 0 ? Vec3(sum.normalized()) : g.face_normals[t];
  };
  switch (feature) {
    case TriangleFeature::vertex_a: return g.vertex_normals[tri[0]];
    case TriangleFeature::vertex_b: return g.vertex_normals[tri[1]];
    case TriangleFeature::vertex_c: return g.vertex_normals[tri[2]];
    case TriangleFeature::edge_ab: return edge(0);
    case TriangleFeature::edge_bc: return edge(1);
    case TriangleFeature::edge_ca: return edge(2);
    default: return g.face_normals[t];
  }
}

}  // namespace

double TriangleMesh::local_distance(const Vec3& p, Vec3& normal) const {
  const auto g = geometry();
  int t;
  const TrianglePoint q = nearest_point(*g, p, t);
  const Vec3 pseudo = pseudonormal(*g, t, q.feature);
  const Vec3 diff = p - q.point;
  const double distance = diff.norm();
  const double sign = diff.dot(pseudo) < 0 ? -1.0 : 1.0;
  // On the surface the direction to the nearest point is undefined: the pseudonormal is the
  // surface's normal there.
  normal = distance > 1e-14 * (1 + q.point.norm()) ? Vec3(sign * diff / distance) : pseudo;
  return sign * distance;
}

Vec3 TriangleMesh::local_velocity(const Vec3& p) const {
  const auto g = geometry();
  int t;
  const TrianglePoint q = nearest_point(*g, p, t);
  const auto& tri = (*g->triangles)[t];
  return q.barycentric[0] * g->velocities.col(tri[0]) + q.barycentric[1] * g->velocities.col(tri[1]) +
         q.barycentric[2] * g->velocities.col(tri[2]);
}

std::string TriangleMesh::describe() const {
  return "triangle mesh of " + std::to_string(geometry()->triangles->size()) + " triangles";
}

void TriangleMesh::set_vertices(const Nodes& vertices, const Nodes* velocities) {
  const auto g = geometry();
  if (vertices.cols() != g->vertices.cols())
    throw InvalidInput("the obstacle mesh has " + std::to_string(g->vertices.cols()) + " vertices, not " +
                       std::to_string(vertices.cols()));
  if (velocities && velocities->cols() != vertices.cols())
    throw InvalidInput("the obstacle mesh has " + std::to_string(vertices.cols()) + " vertices but " +
                       std::to_string(velocities->cols()) + " velocities were given");
  for (Index i = 0; i < vertices.cols(); ++i)
    if (!vertices.col(i).allFinite() || (velocities && !velocities->col(i).allFinite()))
      throw InvalidInput("vertex " + std::to_string(i) + " of the obstacle mesh is not finite (position or velocity)");
  std::shared_ptr<const Geometry> next = make_geometry(
      vertices, velocities ? *velocities : Nodes::Zero(3, vertices.cols()), g->triangles, g->edge_neighbours, &g->bvh);
  std::atomic_store(&geometry_, next);
}

void TriangleMesh::nearest(const Vec3& p, std::array<int, 3>& corners, Vec3& weights) const {
  const auto g = geometry();
  int t;
  const TrianglePoint q = nearest_point(*g, p, t);
  corners = (*g->triangles)[t];
  weights = q.barycentric;
}

Vec3 TriangleMesh::vertex_normal(int vertex) const { return geometry()->vertex_normals[vertex]; }

void TriangleMesh::triangles_near(const Vec3& p, double radius, std::vector<int>& out) const {
  out.clear();
  const double radius2 = radius * radius;
  // The nearest-triangle walk with a bound that never shrinks visits every box within it.
  geometry()->bvh.nearest(p, radius2, [&](int t) {
    out.push_back(t);
    return radius2;
  });
}

Nodes TriangleMesh::vertices() const { return geometry()->vertices; }

Triangles TriangleMesh::triangles() const { return *geometry()->triangles; }

Nodes TriangleMesh::distribute(const Nodes& points, const Nodes& forces) const {
  if (points.cols() != forces.cols())
    throw InvalidInput("distribute needs one force per point: " + std::to_string(points.cols()) + " points, " +
                       std::to_string(forces.cols()) + " forces");
  if (!points.allFinite() || !forces.allFinite()) throw InvalidInput("distribute: points and forces must be finite");
  const auto g = geometry();
  Nodes spread = Nodes::Zero(3, g->vertices.cols());
  for (Index k = 0; k < points.cols(); ++k) {
    int t;
    const TrianglePoint q = nearest_point(*g, points.col(k), t);
    for (int c = 0; c < 3; ++c) spread.col((*g->triangles)[t][c]) += q.barycentric[c] * forces.col(k);
  }
  return spread;
}

}  // namespace corotate
