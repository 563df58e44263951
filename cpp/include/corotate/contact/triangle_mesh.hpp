// A closed triangle mesh as an obstacle: a rigid tool of any shape (a scalpel, a bone, a
// table from a CAD file) or, with its vertices moved every step, another body's surface.
//
// The distance to the surface is exact: the nearest triangle comes from a bounding-volume
// hierarchy (contact/triangle_bvh.hpp). Its sign comes from the angle-weighted pseudonormal
// of the nearest feature (Baerentzen & Aanaes 2005: face normal on a face, the mean of the
// two faces' normals on an edge, the angle-weighted mean of the faces' normals at a corner),
// which is exact for a closed, consistently oriented (2-manifold) mesh. The constructor
// therefore checks that every edge joins exactly two triangles in opposite directions (no
// hole, no fin, no flipped triangle) and turns the mesh outward if it enclosed negative
// volume; self-intersection is not checked.
//
// Moving the vertices (set_vertices, with their velocities) swaps in a new immutable
// geometry: a step that reads the mesh in another thread sees either the old or the new one
// whole, never half of each.
#pragma once

#include <memory>

#include "corotate/contact/obstacle.hpp"
#include "corotate/contact/triangle_bvh.hpp"

namespace corotate {

class TriangleMesh final : public Obstacle {
 public:
  // vertices 3 x n in the obstacle's own frame; triangles' corners index them. Throws
  // InvalidInput naming the first problem: non-finite vertex, index out of range,
  // zero-area triangle, open edge (a hole), an edge of more than two triangles,
  // inconsistent orientation, or no enclosed volume.
  TriangleMesh(const Nodes& vertices, const Triangles& triangles);

  double local_distance(const Vec3& p, Vec3& normal) const override;
  bool deforms() const override { return true; }
  // The velocity (own frame) of the surface point nearest to p: the barycentric mean of its
  // triangle's vertex velocities.
  Vec3 local_velocity(const Vec3& p) const override;
  std::string describe() const override;

  // Moves the vertices (same count, own frame), with their velocities (zero if null). Throws
  // InvalidInput for a wrong count or a non-finite value; the mesh is then unchanged.
  void set_vertices(const Nodes& vertices, const Nodes* velocities = nullptr);
  // The same for a mesh that only its owner reads, from one thread (a part's surface inside
  // its simulation, moved every step): in place, without the new geometry set_vertices
  // allocates so that readers in other threads see either whole. Values unchecked.
  void move_owned_vertices(const Nodes& vertices, const Nodes& velocities);
  Nodes vertices() const;
  Triangles triangles() const;  // outward oriented (possibly reversed from the input)

  // The triangle nearest to p (own frame): its corners (vertex indices) and the barycentric
  // weights of the nearest point on it.
  void nearest(const Vec3& p, std::array<int, 3>& corners, Vec3& weights) const;
  // The outward angle-weighted normal at a vertex (zero for a vertex no triangle uses).
  Vec3 vertex_normal(int vertex) const;
  // The triangles whose bounding boxes come within `radius` of p (own frame), into out
  // (cleared first; its storage is reused): the candidates of a range query, a superset of
  // the triangles within radius.
  void triangles_near(const Vec3& p, double radius, std::vector<int>& out) const;

  // Point forces (own frame) at points on or near the surface, spread onto the vertices by
  // the barycentric weights of each point's nearest surface point: the reaction a body's
  // contacts put on the mesh whose surface they touch.
  Nodes distribute(const Nodes& points, const Nodes& forces) const;

 private:
  struct Geometry;
  struct Nearest;
  std::shared_ptr<const Geometry> geometry() const;
  static std::shared_ptr<Geometry> make_geometry(const Nodes& vertices, const Nodes& velocities,
                                                 std::shared_ptr<const Triangles> triangles,
                                                 std::shared_ptr<const std::vector<int>> edge_neighbours,
                                                 const TriangleBvh* bvh);

  std::shared_ptr<const Geometry> geometry_;  // read and replaced with std::atomic_load/store
};

}  // namespace corotate
