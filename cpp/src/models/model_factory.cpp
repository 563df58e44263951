#include "corotate/models/model_factory.hpp"

#include "corotate/models/corotational_fem.hpp"
#include "corotate/models/hyperelastic_fem.hpp"
#include "corotate/models/linear_fem.hpp"
#include "corotate/models/membrane_fem.hpp"
#include "corotate/materials/fixed_corotated.hpp"
#include "corotate/materials/stable_neo_hookean.hpp"
#include "corotate/materials/stvk.hpp"

namespace corotate {

namespace {
const char* const kModels = "'linear', 'corotational', 'stvk', 'neohookean' or 'corotated'";

template <class E>
std::unique_ptr<ForceModel> make_for_element(const std::string& model, const Nodes& rest, const Connectivity& cells,
                                             const Material& material, const ModelOptions& options) {
  if (model == "linear") return std::make_unique<LinearFEM<E>>(rest, cells, material);
  if (model == "corotational") return std::make_unique<CorotationalFEM<E>>(rest, cells, material);
  if (model == StVK::name) return std::make_unique<HyperelasticFEM<E, StVK>>(rest, cells, material, options.project_psd);
  if (model == StableNeoHookean::name)
    return std::make_unique<HyperelasticFEM<E, StableNeoHookean>>(rest, cells, material, options.project_psd);
  if (model == FixedCorotated::name)
    return std::make_unique<HyperelasticFEM<E, FixedCorotated>>(rest, cells, material, options.project_psd);
  throw InvalidInput("unknown model '" + model + "' (choose " + kModels + ")");
}
}  // namespace

std::unique_ptr<ForceModel> make_model(const std::string& model, const std::string& cell_type, const Nodes& rest,
                                       const Connectivity& cells, const Material& material, const ModelOptions& options) {
  if (cell_type == Tet4::name) return make_for_element<Tet4>(model, rest, cells, material, options);
  if (cell_type == Hex8::name) return make_for_element<Hex8>(model, rest, cells, material, options);
  if (cell_type == Hex20::name) return make_for_element<Hex20>(model, rest, cells, material, options);
  if (cell_type == Tri3::name) {
    if (model == StVK::name) return std::make_unique<MembraneFEM>(rest, cells, material, options.thickness, options.project_psd);
    throw InvalidInput("model '" + model + "' is not available for triangle cells (membranes support 'stvk' only)");
  }
  throw InvalidInput("unsupported cell type '" + cell_type + "' (supported: tetra, hexahedron, hexahedron20, triangle)");
}

}  // namespace corotate
