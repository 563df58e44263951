// A detailed triangle surface carried by a coarse simulated body (the paper's §2.2.2, the
// "two meshes" of its dog model): coupled once before the simulation, each surface vertex is
// assigned to one element of the body and keeps its local coordinates there, so every frame
// its position is a fixed weighted sum of that element's nodes.
//
// Coupling: a vertex inside an element (barycentric coordinates for Tet4, the inverse
// isoparametric map by Newton for Hex8/Hex20; see local_coordinates.hpp) is assigned to it.
// A vertex inside no element is assigned, as in the paper, to the element that minimises the
// criterion (Tet4: sum of |barycentric coordinates| - 1; hexes: the natural-coordinate excess
// outside [-1, 1]), searched among the elements whose bounding box lies within one element
// size of the nearest box; the report says how many such vertices there are and how far out.
// A uniform grid over the element boxes (element_search_grid.hpp) keeps the search local.
//
// Per frame (allocation-free, into caller-owned arrays): positions, area-weighted vertex
// normals of the deformed surface, or the rest normals rotated by each element's rotation
// (the polar rotation of F at the element centre).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

struct EmbeddingSettings {
  // A vertex outside the body farther than this many element sizes (the longest edge of the
  // element's bounding box) is an error: the surface does not belong to the body.
  double max_outside_distance = 1.0;
  void validate() const;
};

struct EmbeddingReport {
  Index outside = 0;  // vertices inside no element
  double max_outside_distance = 0;  // the largest of their distances / element size
  Index farthest_vertex = -1;  // which vertex that is (-1: none outside)
};

class SurfaceEmbedding {
 public:
  using Triangles = Eigen::Matrix<int, 3, Eigen::Dynamic>;  // one column per triangle

  // cell_type  "tetra", "hexahedron" or "hexahedron20" (VTK node order)
  // rest       3 x n rest positions of the body's nodes;  cells  m x k node indices
  // vertices   3 x nv rest positions of the surface's vertices (nv >= 1)
  // triangles  nt x 3 vertex indices (nt may be 0: a point cloud, whose normals are zero)
  // Throws InvalidInput naming the offending node, cell, vertex or triangle.
  SurfaceEmbedding(const std::string& cell_type, const Nodes& rest, const Connectivity& cells, const Nodes& vertices,
                   const Connectivity& triangles, const EmbeddingSettings& settings = {});

  Index num_vertices() const { return vertices_.cols(); }
  Index num_triangles() const { return triangles_.cols(); }
  Index num_body_nodes() const { return num_body_nodes_; }
  int nodes_per_vertex() const { return nodes_per_vertex_; }

  const Nodes& rest_vertices() const { return vertices_; }
  const Triangles& triangles() const { return triangles_; }
  const std::vector<int>& elements() const { return element_; }  // element of each vertex
  const Nodes& local_coordinates() const { return local_; }  // 3 x nv (Tet4: N1..N3)
  const Vec& outside_distances() const { return outside_distance_; }  // / element size; 0 inside
  const EmbeddingReport& report() const { return report_; }
  const Nodes& rest_normals() const { return rest_normals_; }
  // Vertex v is sum_k w_k x_{n_k} over k < nodes_per_vertex(): its element's nodes n and
  // shape-function weights w, from vertex_nodes() and vertex_weights() at v * nodes_per_vertex().
  const std::vector<int>& vertex_nodes() const { return nodes_; }
  const std::vector<double>& vertex_weights() const { return weights_; }

  // Surface positions (3 x nv, written into out) for body positions x (3 x n).
  void embed(Eigen::Ref<const Nodes> x, Eigen::Ref<Nodes> out) const;
  // Area-weighted unit vertex normals (3 x nv, into out) of the surface at positions y
  // (3 x nv): the sum of the incident triangles' (b - a) x (c - a), normalised; zero for a
  // vertex in no triangle of non-zero area.
  void vertex_normals(Eigen::Ref<const Nodes> y, Eigen::Ref<Nodes> out) const;
  // The rest normals rotated by the rotation of each vertex's element at body positions x
  // (3 x n): cheaper than vertex_normals for a fine surface on a coarse body, exact for rigid
  // motions, blind to bending inside an element. Warm-starts each element's rotation from
  // the previous call.
  void rotated_normals(Eigen::Ref<const Nodes> x, Eigen::Ref<Nodes> out);

 private:
  void check_body_positions(const Eigen::Ref<const Nodes>& x) const;
  void check_output(const Eigen::Ref<Nodes>& out, const char* what) const;
  template <class E>
  void couple(const Nodes& rest, const Connectivity& cells, const EmbeddingSettings& settings);

  Index num_body_nodes_ = 0;
  int nodes_per_vertex_ = 0;
  Nodes vertices_;
  Triangles triangles_;
  std::vector<int> element_;
  Nodes local_;
  Vec outside_distance_;
  EmbeddingReport report_;
  std::vector<int> nodes_;  // nodes_per_vertex per vertex: the element's nodes
  std::vector<double> weights_;  // and their shape-function weights
  Nodes rest_normals_;
  // For rotated_normals: the elements that carry vertices, their nodes and dN/dX at the
  // element centre (F = sum_a x_a G_a^T), and a warm-start rotation per element.
  Connectivity cells_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> centre_gradients_;  // k rows per element
  std::vector<int> used_elements_;
  std::vector<Eigen::Quaterniond, Eigen::aligned_allocator<Eigen::Quaterniond>> rotations_;
  std::vector<Mat3> element_rotation_;
};

}  // namespace corotate
