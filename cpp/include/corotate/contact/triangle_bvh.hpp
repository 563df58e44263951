// A bounding-volume hierarchy (axis-aligned boxes) over a triangle mesh's triangles, for the
// nearest triangle to a point in O(log n) instead of O(n).
//
// Built once per topology (median split along the longest axis of the centroids' box, up to
// four triangles per leaf); when the vertices move (a deforming body's surface) the tree keeps
// its shape and only its boxes are recomputed (refit, O(n)): the query stays exact, it only
// prunes less well if the surface has deformed a lot since the build.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

using Triangles = std::vector<std::array<int, 3>>;

class TriangleBvh {
 public:
  TriangleBvh() = default;
  TriangleBvh(const Nodes& vertices, const Triangles& triangles);
  // Same triangles, moved vertices: recompute the boxes.
  void refit(const Nodes& vertices, const Triangles& triangles);

  // Calls visit(triangle) for triangles that may lie within sqrt(best2()) of p, nearest box
  // first; visit returns the new best squared distance (so later boxes prune harder).
  template <class Visit>
  void nearest(const Vec3& p, double best2, Visit&& visit) const;

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int first = 0;  // leaf: its triangles are order_[first, first + count); inner: right child
    int count = 0;  // 0 for an inner node, whose left child is the next node
  };
  int build(const Nodes& vertices, const Triangles& triangles, std::vector<Vec3>& centroids, int begin, int end);

  std::vector<Node> nodes_;
  std::vector<int> order_;
};

template <class Visit>
void TriangleBvh::nearest(const Vec3& p, double best2, Visit&& visit) const {
  if (nodes_.empty()) return;
  std::array<int, 128> stack;  // depth <= 2 log2(n) for the median split: ample
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (node.box.squaredExteriorDistance(p) >= best2) continue;
    if (node.count > 0) {
      for (int k = node.first; k < node.first + node.count; ++k) best2 = visit(order_[k]);
      continue;
    }
    const int left = static_cast<int>(&node - nodes_.data()) + 1, right = node.first;
    const double dl = nodes_[left].box.squaredExteriorDistance(p), dr = nodes_[right].box.squaredExteriorDistance(p);
    // The nearer child is popped first.
    if (dl < dr) {
      if (dr < best2) stack[top++] = right;
      if (dl < best2) stack[top++] = left;
    } else {
      if (dl < best2) stack[top++] = left;
      if (dr < best2) stack[top++] = right;
    }
  }
}

}  // namespace corotate
