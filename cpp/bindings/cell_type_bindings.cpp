// pybind11 glue for the cell-type table and the per-element questions Python asks of a cell
// type (corotate._core.cell_types, cell_volumes, shape_functions, element_matrices). Nothing
// but conversions and one visit over the registered elements.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/elements/cell_types.hpp"
#include "corotate/elements/element_list.hpp"
#include "corotate/elements/element_matrices.hpp"
#include "corotate/models/model_factory.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

namespace {

py::dict facts_dict(const CellTypeFacts& f) {
  py::dict d;
  d["name"] = f.name;
  d["generator_name"] = f.generator_name;
  d["domain"] = f.domain;
  d["dim"] = f.dim;
  d["order"] = f.order;
  d["num_nodes"] = f.num_nodes;
  d["num_corners"] = f.num_corners;
  d["num_stiffness_points"] = f.num_stiffness_points;
  d["reference_nodes"] = f.reference_nodes;
  Eigen::MatrixXi edges(f.edges.size(), 2);
  for (size_t i = 0; i < f.edges.size(); ++i) edges.row(i) << f.edges[i][0], f.edges[i][1];
  d["edges"] = edges;
  const int face_size = f.faces.empty() ? 0 : static_cast<int>(f.faces[0].size());
  Eigen::MatrixXi faces(f.faces.size(), face_size);
  for (size_t i = 0; i < f.faces.size(); ++i)
    for (int j = 0; j < face_size; ++j) faces(i, j) = f.faces[i][j];
  d["faces"] = faces;
  d["mirror"] = Eigen::VectorXi(Eigen::Map<const Eigen::VectorXi>(f.mirror.data(), f.mirror.size()));
  d["models"] = models_for_cell_type(f.name);
  return d;
}

template <class E>
py::dict element_matrices_dict(const PointsIn& points, const Material& material) {
  const Nodes X = nodes_from(points, "element nodes");
  if (X.cols() != E::num_nodes)
    throw InvalidInput(std::string(E::name) + " needs " + std::to_string(E::num_nodes) + " nodes");
  material.validate();
  const auto m = compute_element_matrices<E>(X, material, 0);
  py::dict d;
  d["stiffness"] = Eigen::MatrixXd(m.stiffness);
  d["mass"] = Eigen::MatrixXd(m.mass);
  d["lumped_mass"] = Eigen::VectorXd(m.lumped_mass);
  d["volume"] = m.volume;
  d["centre_gradient"] = Eigen::MatrixXd(m.centre_gradient);
  return d;
}

}  // namespace

void bind_cell_types(py::module_& m) {
  m.def("cell_type_names", &cell_type_names, "Every supported cell type (meshio names), solids first.");
  m.def(
      "cell_types",
      [] {
        py::list out;
        for (const CellTypeFacts& f : cell_types()) out.append(facts_dict(f));
        return out;
      },
      "The cell-type table: for every registered element a dict of name (meshio), generator_name, domain "
      "('simplex' or 'cube'), dim, order, num_nodes, num_corners, num_stiffness_points, reference_nodes "
      "(k, dim), edges (ne, 2) corner pairs (a quadratic element's node num_corners + i sits on edge i), faces "
      "(nf, c) corner nodes of each boundary face counter-clockwise seen from outside (none for membranes), "
      "mirror (k,) the renumbering that turns a cell inside out, models (the force models available).");
  m.def(
      "cell_volumes",
      [](const std::string& cell_type, const PointsIn& points, const CellsIn& cells) {
        return signed_cell_volumes(cell_type, nodes_from(points, "points"), cells_from(cells));
      },
      py::arg("cell_type"), py::arg("points"), py::arg("cells"),
      "Signed volume of every cell (m,), by the element's own quadrature of det(dX/dxi): exact for straight and "
      "curved cells; negative for a mirrored cell. Membranes: the areas.");
  m.def(
      "shape_functions",
      [](const std::string& cell_type, const Eigen::MatrixXd& xi) {
        if (xi.cols() != 3) throw InvalidInput("reference points must have shape (q, 3)");
        py::tuple out;
        visit_solid_element(cell_type, "shape_functions", [&](auto tag) {
          using E = typename decltype(tag)::type;
          Eigen::MatrixXd values(xi.rows(), E::num_nodes), gradients(xi.rows() * E::num_nodes, 3);
          for (Index q = 0; q < xi.rows(); ++q) {
            const Vec3 p = xi.row(q).transpose();
            values.row(q) = E::shape(p).transpose();
            gradients.middleRows(q * E::num_nodes, E::num_nodes) = E::shape_gradient(p);
          }
          out = py::make_tuple(values, gradients);
        });
        return out;
      },
      py::arg("cell_type"), py::arg("xi"),
      "(values (q, k), gradients (q * k, 3)) of the shape functions of a solid cell type at reference points xi "
      "(q, 3); gradient rows q * k + a hold dN_a/dxi at point q.");
  m.def(
      "centre_gradients",
      [](const std::string& cell_type, const PointsIn& points, const CellsIn& cells) {
        const Nodes rest = nodes_from(points, "points");
        const Connectivity c = cells_from(cells);
        Eigen::MatrixXd out;
        visit_solid_element(cell_type, "centre_gradients", [&](auto tag) {
          using E = typename decltype(tag)::type;
          if (c.rows() > 0 && c.cols() != E::num_nodes)
            throw InvalidInput(std::string(E::name) + " cells need " + std::to_string(E::num_nodes) + " nodes each");
          out.resize(c.rows() * E::num_nodes, 3);
          ElementNodes<E> X;
          for (Index e = 0; e < c.rows(); ++e) {
            for (int a = 0; a < E::num_nodes; ++a) {
              if (c(e, a) < 0 || c(e, a) >= rest.cols())
                throw InvalidInput("cell " + std::to_string(e) + " has node index " + std::to_string(c(e, a)) +
                                   " out of range");
              X.col(a) = rest.col(c(e, a));
            }
            out.middleRows(e * E::num_nodes, E::num_nodes) = centre_gradient<E>(X, e);
          }
        });
        return out;
      },
      py::arg("cell_type"), py::arg("points"), py::arg("cells"),
      "Shape-function gradients dN_a/dX at every cell's centre, (m * k, 3): rows e * k + a (F = x_e G there). "
      "Degenerate or inverted cells are rejected by index.");
  m.def(
      "element_matrices",
      [](const std::string& cell_type, const PointsIn& points, const Material& material) {
        py::dict out;
        visit_solid_element(cell_type, "element_matrices", [&](auto tag) {
          out = element_matrices_dict<typename decltype(tag)::type>(points, material);
        });
        return out;
      },
      py::arg("cell_type"), py::arg("points"), py::arg("material"),
      "Precomputed matrices of one element: stiffness (3k x 3k), consistent mass (k x k scalar), lumped_mass (k), "
      "volume.");
}
