#include "corotate/contact/triangle_bvh.hpp"

#include <algorithm>
#include <numeric>

namespace corotate {

namespace {
Eigen::AlignedBox3d triangle_box(const Nodes& vertices, const std::array<int, 3>& t) {
  Eigen::AlignedBox3d box(vertices.col(t[0]));
  box.extend(vertices.col(t[1]).eval());
  box.extend(vertices.col(t[2]).eval());
  return box;
}
}  // namespace

TriangleBvh::TriangleBvh(const Nodes& vertices, const Triangles& triangles) {
  if (triangles.empty()) return;
  order_.resize(triangles.size());
  std::iota(order_.begin(), order_.end(), 0);
  std::vector<Vec3> centroids(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    centroids[t] = (vertices.col(triangles[t][0]) + vertices.col(triangles[t][1]) + vertices.col(triangles[t][2])) / 3;
  nodes_.reserve(2 * triangles.size());
  build(vertices, triangles, centroids, 0, static_cast<int>(triangles.size()));
}

int TriangleBvh::build(const Nodes& vertices, const Triangles& triangles, std::vector<Vec3>& centroids, int begin,
                       int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box, centre_box;
  for (int k = begin; k < end; ++k) {
    box.extend(triangle_box(vertices, triangles[order_[k]]));
    centre_box.extend(centroids[order_[k]]);
  }
  nodes_[index].box = box;
  if (end - begin <= 4) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  int axis;
  centre_box.sizes().maxCoeff(&axis);
  const int middle = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                   [&](int s, int t) { return centroids[s][axis] < centroids[t][axis]; });
  build(vertices, triangles, centroids, begin, middle);  // the left child is index + 1
  const int right = build(vertices, triangles, centroids, middle, end);
  nodes_[index].first = right;
  return index;
}

void TriangleBvh::refit(const Nodes& vertices, const Triangles& triangles) {
  // Children come after their parent in nodes_ (pre-order), so a backward sweep sees both
  // children's new boxes before the parent's.
  for (size_t n = nodes_.size(); n-- > 0;) {
    Node& node = nodes_[n];
    if (node.count > 0) {
      node.box.setEmpty();
      for (int k = node.first; k < node.first + node.count; ++k)
        node.box.extend(triangle_box(vertices, triangles[order_[k]]));
    } else {
      node.box = nodes_[n + 1].box.merged(nodes_[node.first].box);
    }
  }
}

}  // namespace corotate
