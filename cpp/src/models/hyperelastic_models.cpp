// The hyperelastic models: every registered law on every registered solid element, and the
// membrane laws on the membrane elements (registry.hpp).
#include "corotate/fem/assembled_model.hpp"
#include "corotate/models/hyperelastic_kernel.hpp"
#include "corotate/models/registry.hpp"

namespace corotate {

namespace {
template <class Elements, class Laws>
std::unique_ptr<ForceModel> build(const std::string& law, const std::string& cell_type, const Nodes& rest,
                                  const Connectivity& cells, const RegionMaterials& materials,
                                  const ModelOptions& options) {
  std::unique_ptr<ForceModel> model;
  visit_by_name(Elements{}, cell_type, [&](auto element) {
    visit_by_name(Laws{}, law, [&](auto law_tag) {
      using E = typename decltype(element)::type;
      using L = typename decltype(law_tag)::type;
      model = std::make_unique<AssembledModel<HyperelasticKernel<E, L>>>(rest, cells, materials, options);
    });
  });
  return model;
}
}  // namespace

std::unique_ptr<ForceModel> make_hyperelastic_model(const std::string& law, const std::string& cell_type,
                                                    const Nodes& rest, const Connectivity& cells,
                                                    const RegionMaterials& materials, const ModelOptions& options) {
  if (auto model = build<SolidElements, HyperelasticLaws>(law, cell_type, rest, cells, materials, options))
    return model;
  return build<MembraneElements, MembraneLaws>(law, cell_type, rest, cells, materials, options);
}

}  // namespace corotate
