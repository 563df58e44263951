// The facts an element type owns about its shape, and the runtime description of them that
// the rest of the library reads (the cell-type table, cell_types.hpp).
//
// Every element type (tet4.hpp, tet10.hpp, hex8.hpp, hex20.hpp, tri3.hpp) declares:
//   name                  the meshio/VTK cell type ("tetra", ...)
//   generator_name        its name in the structured generators ("tet4", ...)
//   domain                ReferenceDomain::simplex or ::cube: the reference cell
//   dim                   3 for solids, 2 for membranes (reference coordinates in the rest plane)
//   order                 1 (linear) or 2 (quadratic: one node in the middle of each edge)
//   num_nodes, num_corners
//   node(a)               reference coordinates of node a (first dim entries used)
//   edges                 corner pairs; node num_corners + i of a quadratic element sits on edge i
//   faces                 corner nodes of each boundary face, counter-clockwise seen from
//                         outside (none for membranes: a sheet is its own surface)
//   corner_mirror         a permutation of the corners that turns the cell inside out (a cell
//                         read with negative volume is renumbered by it)
// The mirror of every node follows from corner_mirror and the edges (mirror_map below).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

enum class ReferenceDomain { simplex, cube };

inline const char* domain_name(ReferenceDomain d) { return d == ReferenceDomain::simplex ? "simplex" : "cube"; }

// The permutation of all nodes that mirrors a cell: corners by corner_mirror, and the node on
// edge (a, b) to the node on edge (mirror a, mirror b).
template <class E>
std::vector<int> mirror_map() {
  std::vector<int> m(E::corner_mirror.begin(), E::corner_mirror.end());
  if constexpr (E::order == 2) {
    for (const auto& e : E::edges) {
      const int a = E::corner_mirror[e[0]], b = E::corner_mirror[e[1]];
      for (size_t j = 0; j < E::edges.size(); ++j) {
        const auto& f = E::edges[j];
        if ((f[0] == a && f[1] == b) || (f[0] == b && f[1] == a)) m.push_back(E::num_corners + static_cast<int>(j));
      }
    }
  }
  if (static_cast<int>(m.size()) != E::num_nodes)
    throw std::logic_error(std::string(E::name) + ": corner_mirror and edges do not give a mirror of every node");
  return m;
}

// shape() and shape_gradient() of an element E whose values and gradients share their factors
// and are computed together by E::evaluate(xi, values*, gradients*) (Tet10, Hex20).
template <class E, int N>
struct ShapeFromEvaluate {
  using ShapeValues = Eigen::Matrix<double, N, 1>;
  using ShapeGradient = Eigen::Matrix<double, N, 3>;  // row a = dN_a/dxi
  static ShapeValues shape(const Vec3& xi) {
    ShapeValues n;
    E::evaluate(xi, &n, nullptr);
    return n;
  }
  static ShapeGradient shape_gradient(const Vec3& xi) {
    ShapeGradient g;
    E::evaluate(xi, nullptr, &g);
    return g;
  }
};

// Runtime description of one cell type: what Python's Mesh, the generators, the embedding
// and the tests read (bound as corotate._core.cell_types()).
struct CellTypeFacts {
  std::string name, generator_name, domain;
  int dim = 3, order = 1, num_nodes = 0, num_corners = 0, num_stiffness_points = 0;
  Eigen::MatrixXd reference_nodes;  // num_nodes x dim
  std::vector<std::array<int, 2>> edges;
  std::vector<std::vector<int>> faces;
  std::vector<int> mirror;
};

template <class E>
CellTypeFacts describe_element() {
  CellTypeFacts f;
  f.name = E::name;
  f.generator_name = E::generator_name;
  f.domain = domain_name(E::domain);
  f.dim = E::dim;
  f.order = E::order;
  f.num_nodes = E::num_nodes;
  f.num_corners = E::num_corners;
  f.num_stiffness_points = E::num_stiffness_points;
  f.reference_nodes.resize(E::num_nodes, E::dim);
  for (int a = 0; a < E::num_nodes; ++a) f.reference_nodes.row(a) = E::node(a).head(E::dim).transpose();
  f.edges.assign(E::edges.begin(), E::edges.end());
  for (const auto& face : E::faces) f.faces.emplace_back(face.begin(), face.end());
  f.mirror = mirror_map<E>();
  return f;
}

}  // namespace corotate
