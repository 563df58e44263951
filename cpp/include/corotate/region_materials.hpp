// The materials of a body made of regions (the organs of a surgery model, a bar of two
// metals): one Material per region and the region of each cell. A homogeneous body is one
// region, and a Material converts to it, so code written for one material passes it as it
// is. Models take each element's material once, when they precompute the element (its K_e,
// its law, its mass); the per-step code never looks at regions.
#pragma once

#include <vector>

#include "corotate/material.hpp"

namespace corotate {

struct RegionMaterials {
  std::vector<Material> materials;  // by region id: 0, 1, ...
  std::vector<int> cell_regions;    // the region id of each cell; empty: every cell is region 0

  RegionMaterials(const Material& material) : materials{material} {}  // NOLINT(google-explicit-constructor)
  RegionMaterials(std::vector<Material> materials, std::vector<int> cell_regions)
      : materials(std::move(materials)), cell_regions(std::move(cell_regions)) {}

  int region_of(Index cell) const { return cell_regions.empty() ? 0 : cell_regions[cell]; }
  const Material& of_cell(Index cell) const { return materials[region_of(cell)]; }

  // Throws InvalidInput naming the problem: no material, an invalid material (naming its
  // region), a region list whose length is not num_cells, a region id out of range (naming
  // the cell and the id).
  void validate(Index num_cells) const;

  // The materials of the listed cells of this body, in that order (for a model of some of
  // its cells).
  RegionMaterials of_cells(const std::vector<Index>& cells) const;
};

}  // namespace corotate
