#include "corotate/meshes/structured_box.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "corotate/elements/element_list.hpp"

namespace corotate {

namespace {

using Offset = std::array<int, 3>;  // grid steps from a cuboid's minimum corner

// The cell corners inside one cuboid as offsets in {0, 1}^3, for the cuboid with parity
// (i % 2, j % 2, k % 2): one hexahedron, or the 6 Kuhn tets mirrored along the odd axes.
template <class E>
std::vector<std::vector<Offset>> corner_cells(const Offset& parity) {
  std::vector<std::vector<Offset>> out;
  if constexpr (E::domain == ReferenceDomain::cube) {
    std::vector<Offset> hex;
    for (int a = 0; a < E::num_corners; ++a) {
      const Vec3 s = E::node(a);
      hex.push_back({s.x() > 0, s.y() > 0, s.z() > 0});
    }
    out.push_back(hex);
  } else {
    // Each Kuhn tet walks from (0, 0, 0) to (1, 1, 1) along the cuboid's edges, one axis at a
    // time in the order of a permutation; an odd permutation is negatively oriented, as is an
    // odd number of mirrors: nodes 1 and 2 are then swapped.
    std::array<int, 3> perm = {0, 1, 2};
    const int mirrors = parity[0] + parity[1] + parity[2];
    do {
      std::vector<Offset> tet(4, Offset{0, 0, 0});
      for (int s = 0; s < 3; ++s) {
        tet[s + 1] = tet[s];
        ++tet[s + 1][perm[s]];
      }
      const int inversions = (perm[0] > perm[1]) + (perm[0] > perm[2]) + (perm[1] > perm[2]);
      for (Offset& o : tet)
        for (int d = 0; d < 3; ++d)
          if (parity[d]) o[d] = 1 - o[d];
      if ((inversions + mirrors) % 2 == 1) std::swap(tet[1], tet[2]);
      out.push_back(tet);
    } while (std::next_permutation(perm.begin(), perm.end()));
  }
  return out;
}

template <class E>
StructuredMesh build(const std::array<int, 3>& n, const Vec3& size, const Vec3& origin) {
  const int sub = E::order;  // grid points per cell step (2: half steps for the mid-edge nodes)
  const std::array<int, 3> g = {sub * n[0] + 1, sub * n[1] + 1, sub * n[2] + 1};
  const auto grid_index = [&](const Offset& p) { return (Index(p[0]) * g[1] + p[1]) * g[2] + p[2]; };

  // Cells as grid points (corners, then the middle of each edge), and which points are used.
  std::vector<Offset> cell_points;
  std::vector<char> used(size_t(g[0]) * g[1] * g[2], 0);
  Index num_cells = 0;
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k)
        for (const auto& corners : corner_cells<E>({i % 2, j % 2, k % 2})) {
          std::vector<Offset> nodes;
          for (const Offset& o : corners) nodes.push_back({sub * (i + o[0]), sub * (j + o[1]), sub * (k + o[2])});
          if constexpr (E::order == 2)
            for (const auto& e : E::edges) {
              const Offset &a = nodes[e[0]], &b = nodes[e[1]];
              nodes.push_back({(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2});
            }
          for (const Offset& p : nodes) used[grid_index(p)] = 1;
          cell_points.insert(cell_points.end(), nodes.begin(), nodes.end());
          ++num_cells;
        }

  // Used grid points numbered in grid order (x-major, z fastest).
  std::vector<Index> id(used.size(), -1);
  Index count = 0;
  for (size_t p = 0; p < used.size(); ++p)
    if (used[p]) id[p] = count++;
  StructuredMesh m;
  m.cell_type = E::name;
  m.points.resize(3, count);
  for (int i = 0; i < g[0]; ++i)
    for (int j = 0; j < g[1]; ++j)
      for (int k = 0; k < g[2]; ++k) {
        const Index p = id[grid_index({i, j, k})];
        if (p < 0) continue;
        // Coordinates as numpy.linspace computes them: exact at both ends.
        const int steps[3] = {i, j, k};
        for (int d = 0; d < 3; ++d)
          m.points(d, p) = steps[d] == g[d] - 1 ? origin(d) + size(d) : origin(d) + steps[d] * (size(d) / (g[d] - 1));
      }
  m.cells.resize(num_cells, E::num_nodes);
  for (Index c = 0; c < num_cells; ++c)
    for (int a = 0; a < E::num_nodes; ++a) m.cells(c, a) = int(id[grid_index(cell_points[c * E::num_nodes + a])]);
  return m;
}

}  // namespace

StructuredMesh structured_box(const std::string& element, const std::array<int, 3>& cells, const Vec3& size,
                              const Vec3& origin) {
  for (int d = 0; d < 3; ++d) {
    if (cells[d] < 1) throw InvalidInput("cells must be three integers >= 1");
    if (!(size(d) > 0) || !std::isfinite(size(d))) throw InvalidInput("size must be finite and positive");
    if (!std::isfinite(origin(d))) throw InvalidInput("origin must be finite");
  }
  StructuredMesh out;
  std::vector<std::string> names;
  bool found = false;
  for_each_type(SolidElements{}, [&](auto tag) {
    using E = typename decltype(tag)::type;
    names.push_back(E::generator_name);
    if (element == E::generator_name) out = build<E>(cells, size, origin), found = true;
  });
  if (!found) throw InvalidInput("unknown element '" + element + "'; choose one of " + joined(names));
  return out;
}

}  // namespace corotate
