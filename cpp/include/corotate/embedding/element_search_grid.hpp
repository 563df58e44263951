// A uniform grid over the bounding boxes of a mesh's elements, to find the elements near a
// point without looking at all of them (coupling 1,000,000 surface vertices to 100,000
// elements visits a handful of elements per vertex instead of every element).
#pragma once

#include <vector>

#include "corotate/common.hpp"

namespace corotate {

class ElementSearchGrid {
 public:
  // lower, upper: 3 x m corners of the elements' axis-aligned bounding boxes (m >= 1).
  // The cell size is chosen so that the grid has about as many cells as elements.
  ElementSearchGrid(const Nodes& lower, const Nodes& upper);

  // Elements whose box may contain p: those registered in p's grid cell (an empty range when
  // p lies outside the grid). Pointers into the grid, valid while it lives.
  std::pair<const int*, const int*> candidates(const Vec3& p) const;

  // Calls visit(element) for the elements registered in every grid cell that overlaps the
  // cube of half-width radius around p (an element can be visited more than once).
  template <class Visit>
  void visit_near(const Vec3& p, double radius, Visit&& visit) const {
    const Eigen::Array3i lo = cell_of(p.array() - radius), hi = cell_of(p.array() + radius);
    for (int k = lo.z(); k <= hi.z(); ++k)
      for (int j = lo.y(); j <= hi.y(); ++j)
        for (int i = lo.x(); i <= hi.x(); ++i) {
          const int c = (k * dims_.y() + j) * dims_.x() + i;
          for (int s = offsets_[c]; s < offsets_[c + 1]; ++s) visit(elements_[s]);
        }
  }

  double cell_size() const { return cell_size_; }
  // Half the diagonal of the whole grid plus the distance of p from its centre: a radius
  // whose cube around p covers every cell.
  double covering_radius(const Vec3& p) const;

 private:
  Eigen::Array3i cell_of(const Eigen::Array3d& p) const;  // clamped into the grid

  Eigen::Array3d origin_;
  double cell_size_ = 1;
  Eigen::Array3i dims_;
  std::vector<int> offsets_;  // CSR: elements of cell c are elements_[offsets_[c] .. offsets_[c + 1])
  std::vector<int> elements_;
};

}  // namespace corotate
