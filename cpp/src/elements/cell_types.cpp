#include "corotate/elements/cell_types.hpp"

#include "corotate/elements/element_geometry.hpp"
#include "corotate/elements/element_list.hpp"

namespace corotate {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i)
    out += (i ? (i + 1 == names.size() ? " or '" : ", '") : "'") + names[i] + "'";
  return out;
}

std::vector<std::string> cell_type_names() {
  std::vector<std::string> names = names_of(SolidElements{});
  for (const auto& cell : names_of(MembraneElements{})) names.push_back(cell);
  return names;
}

std::vector<CellTypeFacts> cell_types() {
  std::vector<CellTypeFacts> table;
  const auto add = [&](auto tag) { table.push_back(describe_element<typename decltype(tag)::type>()); };
  for_each_type(SolidElements{}, add);
  for_each_type(MembraneElements{}, add);
  return table;
}

namespace {

template <class E>
Vec volumes_of(const Nodes& rest, const Connectivity& cells) {
  if (cells.rows() > 0 && cells.cols() != E::num_nodes)
    throw InvalidInput(std::string(E::name) + " cells need " + std::to_string(E::num_nodes) + " nodes each");
  for (Index e = 0; e < cells.rows(); ++e)
    for (int a = 0; a < E::num_nodes; ++a)
      if (cells(e, a) < 0 || cells(e, a) >= rest.cols())
        throw InvalidInput("cell " + std::to_string(e) + " has node index " + std::to_string(cells(e, a)) +
                           " out of range [0, " + std::to_string(rest.cols()) + ")");
  Vec volume(cells.rows());
  ElementNodes<E> X;
  for (Index e = 0; e < cells.rows(); ++e) {
    for (int a = 0; a < E::num_nodes; ++a) X.col(a) = rest.col(cells(e, a));
    double v = 0;
    if constexpr (E::dim == 2) {
      v = 0.5 * (X.col(1) - X.col(0)).cross(X.col(2) - X.col(0)).norm();
    } else {
      const QuadratureRule& rule = E::mass_rule();
      for (size_t q = 0; q < rule.points.size(); ++q)
        v += rule.weights[q] * (X * E::shape_gradient(rule.points[q])).determinant();
    }
    volume(e) = v;
  }
  return volume;
}

}  // namespace

Vec signed_cell_volumes(const std::string& cell_type, const Nodes& rest, const Connectivity& cells) {
  Vec out;
  const auto run = [&](auto tag) { out = volumes_of<typename decltype(tag)::type>(rest, cells); };
  if (!visit_by_name(SolidElements{}, cell_type, run) && !visit_by_name(MembraneElements{}, cell_type, run))
    throw InvalidInput("unsupported cell type '" + cell_type + "' (supported: " + joined(cell_type_names()) + ")");
  return out;
}

}  // namespace corotate
