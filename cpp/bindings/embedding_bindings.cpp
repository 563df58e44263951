// pybind11 glue for the embedded render surface (corotate._core.SurfaceEmbedding). Nothing
// but conversions; per-frame calls read and write the caller's NumPy arrays in place.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/embedding/surface_embedding.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

namespace {

// An (n, 3) float64 C-contiguous array seen as 3 x n nodes (no copy; forcecast in PointsIn
// copies only arrays of another dtype or layout).
Eigen::Map<const Nodes> nodes_view(const PointsIn& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3) throw InvalidInput(std::string(what) + " must have shape (n, 3)");
  return {a.data(), 3, a.shape(0)};
}

// The caller's output array, written in place: it must be a writable (rows, 3) float64
// C-contiguous array, else a copy would be written and the caller would see nothing.
Eigen::Map<Nodes> output_view(py::array& a, Index rows, const char* what) {
  const bool ok = a.dtype().equal(py::dtype::of<double>()) && a.ndim() == 2 && a.shape(0) == rows && a.shape(1) == 3 &&
                  (a.flags() & py::array::c_style) && a.writeable();
  if (!ok)
    throw InvalidInput(std::string(what) + " must be a writable C-contiguous float64 array of shape (" +
                       std::to_string(rows) + ", 3)");
  return {static_cast<double*>(a.mutable_data()), 3, rows};
}

py::array_t<double> rows_of(const Nodes& x) { return py::cast(Eigen::MatrixXd(x.transpose())); }

}  // namespace

void bind_embedding(py::module_& m) {
  py::class_<SurfaceEmbedding>(m, "SurfaceEmbedding")
      .def(py::init([](const std::string& cell_type, const PointsIn& points, const CellsIn& cells,
                       const PointsIn& vertices, const CellsIn& triangles, double max_outside_distance) {
             const Nodes rest = nodes_from(points, "points"), surface = nodes_from(vertices, "vertices");
             if (triangles.ndim() != 2 || triangles.shape(1) != 3)
               throw InvalidInput("triangles must have shape (nt, 3)");
             const Connectivity tri = cells_from(triangles);
             py::gil_scoped_release release;
             return std::make_unique<SurfaceEmbedding>(cell_type, rest, cells_from(cells), surface, tri,
                                                       EmbeddingSettings{max_outside_distance});
           }),
           py::arg("cell_type"), py::arg("points"), py::arg("cells"), py::arg("vertices"), py::arg("triangles"),
           py::arg("max_outside_distance") = EmbeddingSettings{}.max_outside_distance,
           "Couple a triangle surface (vertices (nv, 3), triangles (nt, 3)) to a body mesh (cell_type, points (n, "
           "3), cells (m, k)); see embedding/surface_embedding.hpp.")
      .def_property_readonly("num_vertices", &SurfaceEmbedding::num_vertices)
      .def_property_readonly("num_triangles", &SurfaceEmbedding::num_triangles)
      .def_property_readonly("num_body_nodes", &SurfaceEmbedding::num_body_nodes)
      .def_property_readonly(
          "elements",
          [](const SurfaceEmbedding& s) {
            return Eigen::VectorXi(Eigen::Map<const Eigen::VectorXi>(s.elements().data(), Index(s.elements().size())));
          })
      .def_property_readonly("local_coordinates",
                             [](const SurfaceEmbedding& s) { return rows_of(s.local_coordinates()); })
      .def_property_readonly("outside_distances", [](const SurfaceEmbedding& s) { return Vec(s.outside_distances()); })
      .def_property_readonly("rest_normals", [](const SurfaceEmbedding& s) { return rows_of(s.rest_normals()); })
      .def_property_readonly(
          "vertex_stencils",
          [](const SurfaceEmbedding& s) {
            const Index k = s.nodes_per_vertex(), nv = s.num_vertices();
            Eigen::Matrix<Index, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> nodes(nv, k);
            Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> weights(nv, k);
            for (Index v = 0; v < nv; ++v)
              for (Index j = 0; j < k; ++j) {
                nodes(v, j) = s.vertex_nodes()[v * k + j];
                weights(v, j) = s.vertex_weights()[v * k + j];
              }
            return py::make_tuple(nodes, weights);
          },
          "(nodes (nv, k), weights (nv, k)): vertex v is sum_j weights[v, j] x[nodes[v, j]].")
      .def_property_readonly("report",
                             [](const SurfaceEmbedding& s) {
                               py::dict d;
                               d["outside"] = s.report().outside;
                               d["max_outside_distance"] = s.report().max_outside_distance;
                               d["farthest_vertex"] = s.report().farthest_vertex;
                               return d;
                             })
      .def(
          "embed",
          [](const SurfaceEmbedding& s, const PointsIn& x, py::array& out) {
            s.embed(nodes_view(x, "body positions"), output_view(out, s.num_vertices(), "out"));
          },
          py::arg("positions"), py::arg("out"),
          "Write the surface positions for body positions (n, 3) into out (nv, 3) in place.")
      .def(
          "vertex_normals",
          [](const SurfaceEmbedding& s, const PointsIn& y, py::array& out) {
            s.vertex_normals(nodes_view(y, "surface positions"), output_view(out, s.num_vertices(), "out"));
          },
          py::arg("surface_positions"), py::arg("out"),
          "Write the area-weighted unit vertex normals at surface positions (nv, 3) into out (nv, 3) in place.")
      .def(
          "rotated_normals",
          [](SurfaceEmbedding& s, const PointsIn& x, py::array& out) {
            s.rotated_normals(nodes_view(x, "body positions"), output_view(out, s.num_vertices(), "out"));
          },
          py::arg("positions"), py::arg("out"),
          "Write the rest normals rotated by each vertex's element rotation at body positions (n, 3) into out in "
          "place.");
}
