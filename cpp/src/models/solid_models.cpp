// The linear and co-rotational models for every registered solid element (registry.hpp).
#include "corotate/fem/assembled_model.hpp"
#include "corotate/models/corotational_kernel.hpp"
#include "corotate/models/linear_kernel.hpp"
#include "corotate/models/registry.hpp"

namespace corotate {

std::unique_ptr<ForceModel> make_linear_model(const std::string& cell_type, const Nodes& rest,
                                              const Connectivity& cells, const RegionMaterials& materials,
                                              const ModelOptions& options) {
  std::unique_ptr<ForceModel> model;
  visit_by_name(SolidElements{}, cell_type, [&](auto element) {
    using E = typename decltype(element)::type;
    model = std::make_unique<AssembledModel<LinearKernel<E>>>(rest, cells, materials, options);
  });
  return model;
}

std::unique_ptr<ForceModel> make_corotational_model(const std::string& cell_type, const Nodes& rest,
                                                    const Connectivity& cells, const RegionMaterials& materials,
                                                    const ModelOptions& options) {
  std::unique_ptr<ForceModel> model;
  visit_by_name(SolidElements{}, cell_type, [&](auto element) {
    using E = typename decltype(element)::type;
    model = std::make_unique<AssembledModel<CorotationalKernel<E>>>(rest, cells, materials, options);
  });
  return model;
}

}  // namespace corotate
