// The point of a triangle nearest to a given point, and which feature of the triangle
// (its face, one of its edges or one of its corners) that point lies on: the feature decides
// which pseudonormal signs the distance (contact/triangle_mesh.hpp).
#pragma once

#include "corotate/common.hpp"

namespace corotate {

enum class TriangleFeature { face, vertex_a, vertex_b, vertex_c, edge_ab, edge_bc, edge_ca };

struct TrianglePoint {
  Vec3 point;
  Vec3 barycentric;  // weights of a, b, c: point = w_a a + w_b b + w_c c
  TriangleFeature feature;
};

// By the Voronoi regions of the triangle's features (Ericson, Real-Time Collision Detection,
// 5.1.5): a handful of dot products, no division except on the winning feature.
TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace corotate
