// The edges of a closed, consistently oriented triangle surface, with the two triangles each
// joins: what edge-against-edge contact (contact_set.hpp) walks and how it tells a convex
// edge (a ridge, which another surface's edge can touch) from a flat or concave one.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "corotate/common.hpp"
#include "corotate/contact/triangle_bvh.hpp"  // Triangles

namespace corotate {

struct SurfaceEdges {
  // Edge e runs from vertices[e][0] to vertices[e][1] in the winding of triangle faces[e][0]
  // (and the other way round in faces[e][1]); opposite[e][k] is the corner of faces[e][k]
  // that is not on the edge.
  std::vector<std::array<int, 2>> vertices, faces, opposite;
  std::vector<std::array<int, 3>> of_triangle;  // triangle t's edges (corners 0-1, 1-2, 2-0)
  int size() const { return static_cast<int>(vertices.size()); }
};

// Throws InvalidInput, naming the surface (`name`) and the edge, for an edge that does not
// join exactly two triangles in opposite directions: a hole, a fin, a flipped triangle.
SurfaceEdges surface_edges(const Triangles& triangles, const std::string& name = "the surface");

// Whether edge e is convex at the vertex positions (3 x n) given the triangles' unit normals
// (3 x m): the opposite corner of its second triangle lies behind the first's plane by more
// than `flat` times the edge's length (a ridge, not a flat or a valley).
bool convex_edge(const SurfaceEdges& edges, int e, const Nodes& positions, const Nodes& normals, double flat);

}  // namespace corotate
