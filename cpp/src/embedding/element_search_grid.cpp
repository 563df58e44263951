#include "corotate/embedding/element_search_grid.hpp"

#include <algorithm>
#include <cmath>

namespace corotate {

ElementSearchGrid::ElementSearchGrid(const Nodes& lower, const Nodes& upper) {
  const Index m = lower.cols();
  origin_ = lower.rowwise().minCoeff().array();
  const Eigen::Array3d extent = upper.rowwise().maxCoeff().array() - origin_;
  // About one cell per element, and never smaller than the mean element box (so that an
  // element is registered in a few cells, not hundreds).
  const double volume = std::max(extent.prod(), 1e-300);
  const Eigen::Array3d mean_box = (upper - lower).rowwise().mean().array();
  cell_size_ = std::max({std::cbrt(volume / double(m)), mean_box.maxCoeff(), 1e-12 * extent.maxCoeff(), 1e-300});
  for (int d = 0; d < 3; ++d) dims_(d) = std::clamp(int(std::ceil(extent(d) / cell_size_)), 1, 1 << 10);

  const Index cells = Index(dims_.prod());
  std::vector<int> counts(cells + 1, 0);
  const auto for_cells = [&](Index e, auto&& f) {
    const Eigen::Array3i lo = cell_of(lower.col(e).array()), hi = cell_of(upper.col(e).array());
    for (int k = lo.z(); k <= hi.z(); ++k)
      for (int j = lo.y(); j <= hi.y(); ++j)
        for (int i = lo.x(); i <= hi.x(); ++i) f((k * dims_.y() + j) * dims_.x() + i);
  };
  for (Index e = 0; e < m; ++e) for_cells(e, [&](int c) { ++counts[c + 1]; });
  for (Index c = 0; c < cells; ++c) counts[c + 1] += counts[c];
  offsets_ = counts;
  elements_.resize(offsets_.back());
  for (Index e = 0; e < m; ++e) for_cells(e, [&](int c) { elements_[counts[c]++] = int(e); });
}

Eigen::Array3i ElementSearchGrid::cell_of(const Eigen::Array3d& p) const {
  Eigen::Array3i c;
  for (int d = 0; d < 3; ++d) {
    const double s = std::floor((p(d) - origin_(d)) / cell_size_);
    c(d) = int(std::clamp(s, 0.0, double(dims_(d) - 1)));  // clamp as double: no int overflow far away
  }
  return c;
}

std::pair<const int*, const int*> ElementSearchGrid::candidates(const Vec3& p) const {
  const Eigen::Array3d s = ((p.array() - origin_) / cell_size_).floor();
  if ((s < 0).any() || (s >= dims_.cast<double>()).any() || !p.allFinite()) return {nullptr, nullptr};
  const Eigen::Array3i c = s.cast<int>();
  const int cell = (c.z() * dims_.y() + c.y()) * dims_.x() + c.x();
  return {elements_.data() + offsets_[cell], elements_.data() + offsets_[cell + 1]};
}

double ElementSearchGrid::covering_radius(const Vec3& p) const {
  const Eigen::Array3d half = 0.5 * cell_size_ * dims_.cast<double>();
  return (p.array() - (origin_ + half)).abs().maxCoeff() + half.maxCoeff();
}

}  // namespace corotate
