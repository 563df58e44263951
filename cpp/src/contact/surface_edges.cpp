#include "corotate/contact/surface_edges.hpp"

#include <algorithm>
#include <string>

namespace corotate {

SurfaceEdges surface_edges(const Triangles& triangles, const std::string& name) {
  // Every directed edge, sorted by its undirected pair: an edge of a closed, consistently
  // oriented surface is two neighbours, one in each direction.
  struct Half {
    int low, high, triangle, corner;  // the edge runs from corner to corner + 1 (mod 3)
    bool forward;                     // low -> high in the triangle's winding
  };
  std::vector<Half> halves;
  halves.reserve(3 * triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int i = triangles[t][k], j = triangles[t][(k + 1) % 3];
      halves.push_back({std::min(i, j), std::max(i, j), static_cast<int>(t), k, i < j});
    }
  std::sort(halves.begin(), halves.end(),
            [](const Half& p, const Half& q) { return p.low != q.low ? p.low < q.low : p.high < q.high; });
  SurfaceEdges out;
  out.of_triangle.assign(triangles.size(), {-1, -1, -1});
  for (size_t g = 0; g < halves.size();) {
    size_t end = g + 1;
    while (end < halves.size() && halves[end].low == halves[g].low && halves[end].high == halves[g].high) ++end;
    const Half& p = halves[g];
    const std::string edge = "(" + std::to_string(p.low) + ", " + std::to_string(p.high) + ")";
    if (end - g == 1)
      throw InvalidInput(name + " is not closed: edge " + edge + " of triangle " + std::to_string(p.triangle) +
                         " belongs to no other triangle (a hole)");
    if (end - g > 2)
      throw InvalidInput(name + " is not a surface: edge " + edge + " is shared by " + std::to_string(end - g) +
                         " triangles");
    const Half& q = halves[g + 1];
    if (p.forward == q.forward)
      throw InvalidInput(name + " is not consistently oriented: triangles " + std::to_string(p.triangle) + " and " +
                         std::to_string(q.triangle) + " run along edge " + edge + " the same way");
    const int e = out.size();
    const auto& first = triangles[p.triangle];
    const auto& second = triangles[q.triangle];
    out.vertices.push_back({first[p.corner], first[(p.corner + 1) % 3]});
    out.faces.push_back({p.triangle, q.triangle});
    out.opposite.push_back({first[(p.corner + 2) % 3], second[(q.corner + 2) % 3]});
    out.of_triangle[p.triangle][p.corner] = e;
    out.of_triangle[q.triangle][q.corner] = e;
    g = end;
  }
  return out;
}

bool convex_edge(const SurfaceEdges& edges, int e, const Nodes& positions, const Nodes& normals, double flat) {
  const Vec3 from = positions.col(edges.vertices[e][0]);
  const double length = (positions.col(edges.vertices[e][1]) - from).norm();
  const Vec3 n0 = normals.col(edges.faces[e][0]);
  return n0.dot(positions.col(edges.opposite[e][1]) - from) < -flat * length;
}

}  // namespace corotate
