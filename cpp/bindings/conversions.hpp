// Conversions between NumPy arrays and the core's types, shared by the binding files.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <limits>
#include <string>

#include "corotate/models/force_model.hpp"

namespace corotate::bindings {

namespace py = pybind11;

using PointsIn = py::array_t<double, py::array::c_style | py::array::forcecast>;
using CellsIn = py::array_t<long long, py::array::c_style | py::array::forcecast>;

// (n, 3) array -> 3 x n nodes (a copy).
inline Nodes nodes_from(const PointsIn& points, const char* what) {
  if (points.ndim() != 2 || points.shape(1) != 3) throw InvalidInput(std::string(what) + " must have shape (n, 3)");
  Nodes x(3, points.shape(0));
  std::copy(points.data(), points.data() + points.size(), x.data());
  return x;
}

// (m, k) integer array -> connectivity, with indices that fit an int.
inline Connectivity cells_from(const CellsIn& cells) {
  if (cells.ndim() != 2) throw InvalidInput("cells must have shape (m, nodes_per_cell)");
  Connectivity c(cells.shape(0), cells.shape(1));
  for (py::ssize_t k = 0; k < cells.size(); ++k) {
    const long long v = cells.data()[k];
    if (v < 0 || v > std::numeric_limits<int>::max())
      throw InvalidInput("cell " + std::to_string(k / cells.shape(1)) + " refers to node " + std::to_string(v) +
                         ", out of range");
    c.data()[k] = static_cast<int>(v);
  }
  return c;
}

// Positions (or velocities...) for a model: (n, 3), one row per node, finite. what: the
// array's name, one: the name of one row ("positions", "position").
inline Nodes checked_positions(const ForceModel& model, const PointsIn& x, const char* what = "positions",
                               const char* one = "position") {
  Nodes X = nodes_from(x, what);
  if (X.cols() != model.num_nodes()) throw InvalidInput(std::string(what) + " must have one row per node");
  if (Index i = first_non_finite_node(X); i >= 0)
    throw InvalidInput(std::string(one) + " of node " + std::to_string(i) + " is not finite");
  return X;
}

// (n, 3) NumPy view of a 3 x n buffer owned by `owner` (no copy; writable).
inline py::array node_view(Nodes& x, py::handle owner) {
  return py::array_t<double>({x.cols(), Index(3)}, {Index(3 * sizeof(double)), Index(sizeof(double))}, x.data(), owner);
}

// A BlockSparseMatrix as a scipy-ready CSR triple (data, indices, indptr).
inline py::tuple to_csr(const BlockSparseMatrix& A) {
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> s;
  A.copy_to(s);  // symmetric: the CSC arrays are also the CSR arrays
  Eigen::VectorXd data = Eigen::Map<const Eigen::VectorXd>(s.valuePtr(), s.nonZeros());
  Eigen::VectorXi indices = Eigen::Map<const Eigen::VectorXi>(s.innerIndexPtr(), s.nonZeros());
  Eigen::VectorXi indptr = Eigen::Map<const Eigen::VectorXi>(s.outerIndexPtr(), s.outerSize() + 1);
  return py::make_tuple(data, indices, indptr);
}

}  // namespace corotate::bindings
