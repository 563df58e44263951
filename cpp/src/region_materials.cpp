#include "corotate/region_materials.hpp"

#include <sstream>

namespace corotate {

void RegionMaterials::validate(Index num_cells) const {
  if (materials.empty()) throw InvalidInput("a body needs at least one material");
  for (size_t r = 0; r < materials.size(); ++r) {
    try {
      materials[r].validate();
    } catch (const InvalidInput& e) {
      if (materials.size() == 1) throw;
      throw InvalidInput("material of region " + std::to_string(r) + ": " + e.what());
    }
  }
  if (cell_regions.empty()) return;
  if (static_cast<Index>(cell_regions.size()) != num_cells) {
    std::ostringstream msg;
    msg << "regions: one region id per cell is needed, got " << cell_regions.size() << " for " << num_cells << " cells";
    throw InvalidInput(msg.str());
  }
  for (Index e = 0; e < num_cells; ++e) {
    const int r = cell_regions[e];
    if (r < 0 || r >= static_cast<int>(materials.size())) {
      std::ostringstream msg;
      msg << "cell " << e << " has region id " << r << ", which has no material (" << materials.size()
          << " material(s) given, for region ids 0.." << materials.size() - 1 << ")";
      throw InvalidInput(msg.str());
    }
  }
}

RegionMaterials RegionMaterials::of_cells(const std::vector<Index>& cells) const {
  if (cell_regions.empty()) return *this;
  std::vector<int> regions;
  regions.reserve(cells.size());
  for (Index e : cells) regions.push_back(cell_regions[e]);
  return {materials, regions};
}

}  // namespace corotate
