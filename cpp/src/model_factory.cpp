#include "corotate/models/model_factory.hpp"

#include "corotate/models/corotational_fem.hpp"
#include "corotate/models/linear_fem.hpp"

namespace corotate {

namespace {
template <class E>
std::unique_ptr<ForceModel> make_for_element(const std::string& model, const Nodes& rest, const Connectivity& cells,
                                             const Material& material) {
  if (model == "linear") return std::make_unique<LinearFEM<E>>(rest, cells, material);
  if (model == "corotational") return std::make_unique<CorotationalFEM<E>>(rest, cells, material);
  throw InvalidInput("unknown model '" + model + "' (choose 'linear' or 'corotational')");
}
}  // namespace

std::unique_ptr<ForceModel> make_model(const std::string& model, const std::string& cell_type, const Nodes& rest,
                                       const Connectivity& cells, const Material& material) {
  if (cell_type == Tet4::name) return make_for_element<Tet4>(model, rest, cells, material);
  if (cell_type == Hex8::name) return make_for_element<Hex8>(model, rest, cells, material);
  if (cell_type == Hex20::name) return make_for_element<Hex20>(model, rest, cells, material);
  throw InvalidInput("unsupported cell type '" + cell_type + "' (supported: tetra, hexahedron, hexahedron20)");
}

}  // namespace corotate
