// pybind11 glue for the mesh generators (corotate._core.structured_box). Nothing but conversions.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "corotate/meshes/structured_box.hpp"

namespace py = pybind11;
using namespace corotate;

void bind_meshes(py::module_& m) {
  m.def(
      "structured_box",
      [](const std::string& element, const std::array<int, 3>& cells, const Vec3& size, const Vec3& origin) {
        const StructuredMesh mesh = structured_box(element, cells, size, origin);
        using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
        using Cells = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
        return py::make_tuple(Points(mesh.points.transpose()), Cells(mesh.cells), mesh.cell_type);
      },
      py::arg("element"), py::arg("cells"), py::arg("size"), py::arg("origin"),
      "(points (n, 3), cells (m, k), cell_type) of the structured mesh of the box [origin, origin + size] with "
      "cells (nx, ny, nz) cuboids of the solid element named by its generator name (see meshes/structured_box.hpp).");
}
