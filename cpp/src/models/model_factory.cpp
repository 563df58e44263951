#include "corotate/models/model_factory.hpp"

#include <algorithm>

#include "corotate/models/registry.hpp"

namespace corotate {

void check_renamed_model(const std::string& name) {
  struct Renamed {
    const char *old_name, *new_name, *note;
  };
  // Old names of models, kept so that code written for them fails with the new name.
  static const Renamed renamed[] = {
      {"corotated", "fixed_corotated",
       " (Stomakhin's fixed co-rotated law); 'corotational' is the paper's co-rotated linear FEM"},
  };
  for (const Renamed& r : renamed)
    if (name == r.old_name) throw InvalidInput("model '" + name + "' was renamed '" + r.new_name + "'" + r.note);
}

std::vector<std::string> model_names() {
  std::vector<std::string> names = {"linear", "corotational"};
  for (const auto& law : names_of(HyperelasticLaws{})) names.push_back(law);
  return names;
}

std::vector<std::string> models_for_cell_type(const std::string& cell_type) {
  bool solid = false, membrane = false;
  visit_by_name(SolidElements{}, cell_type, [&](auto) { solid = true; });
  visit_by_name(MembraneElements{}, cell_type, [&](auto) { membrane = true; });
  if (solid) return model_names();
  if (membrane) return names_of(MembraneLaws{});
  return {};
}

std::unique_ptr<ForceModel> make_model(const std::string& model, const std::string& cell_type, const Nodes& rest,
                                       const Connectivity& cells, const RegionMaterials& materials,
                                       const ModelOptions& options) {
  const std::vector<std::string> models = model_names(), available = models_for_cell_type(cell_type);
  if (available.empty())
    throw InvalidInput("unsupported cell type '" + cell_type + "' (supported: " + joined(cell_type_names()) + ")");
  check_renamed_model(model);
  if (std::find(models.begin(), models.end(), model) == models.end())
    throw InvalidInput("unknown model '" + model + "' (choose " + joined(models) + ")");
  if (std::find(available.begin(), available.end(), model) == available.end())
    throw InvalidInput("model '" + model + "' is not available for " + cell_type + " cells (choose " +
                       joined(available) + ")");
  std::unique_ptr<ForceModel> built;
  if (model == "linear") built = make_linear_model(cell_type, rest, cells, materials, options);
  else if (model == "corotational") built = make_corotational_model(cell_type, rest, cells, materials, options);
  else built = make_hyperelastic_model(model, cell_type, rest, cells, materials, options);
  if (!built) throw InvalidInput("model '" + model + "' is not available for " + cell_type + " cells");
  return built;
}

}  // namespace corotate
