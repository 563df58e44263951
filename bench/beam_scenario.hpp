// The standard benchmark scenario (bench/README.md): a 5 x 1 x 1 m beam along x, clamped at
// x = 0, sagging under gravity from rest (tets or Hex8); and a TetGen reader for user meshes.
#pragma once

#include <array>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "corotate/common.hpp"
#include "corotate/elements/hex8.hpp"

namespace corotate::bench {

// "a,b,c" -> {"a", "b", "c"}: the benchmark's list options.
inline std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= s.size()) {
    const size_t comma = s.find(',', start);
    out.push_back(s.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

// --sizes 1,2,4: the beam's refinement factors.
inline std::vector<int> parse_sizes(const std::string& list) {
  std::vector<int> sizes;
  for (const auto& s : split_list(list)) {
    size_t used = 0;
    int size = 0;
    try {
      size = std::stoi(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != s.size() || size < 1)
      throw InvalidInput("--sizes takes positive integers separated by commas, got '" + list + "'");
    sizes.push_back(size);
  }
  return sizes;
}

struct TetMesh {
  Nodes points;
  Connectivity cells;
};

// nx x ny x nz cubes over [0, lx] x [0, ly] x [0, lz], each cut into 6 tets that share the
// cube's main diagonal (Kuhn split, conforming across cubes).
inline TetMesh structured_tet_beam(int nx, int ny, int nz, double lx, double ly, double lz) {
  TetMesh m;
  auto id = [&](int i, int j, int k) { return (i * (ny + 1) + j) * (nz + 1) + k; };
  m.points.resize(3, (nx + 1) * (ny + 1) * (nz + 1));
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j)
      for (int k = 0; k <= nz; ++k) m.points.col(id(i, j, k)) = Vec3(lx * i / nx, ly * j / ny, lz * k / nz);
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  m.cells.resize(6 * nx * ny * nz, 4);
  int e = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        for (const auto& p : perms) {
          std::array<int, 3> c = {i, j, k};
          int tet[4];
          tet[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            tet[s + 1] = id(c[0], c[1], c[2]);
          }
          const Mat3 D = (Mat3() << m.points.col(tet[1]) - m.points.col(tet[0]),
                          m.points.col(tet[2]) - m.points.col(tet[0]), m.points.col(tet[3]) - m.points.col(tet[0]))
                             .finished();
          if (D.determinant() < 0) std::swap(tet[1], tet[2]);
          for (int a = 0; a < 4; ++a) m.cells(e, a) = tet[a];
          ++e;
        }
  return m;
}

// The same beam of nx x ny x nz cubes as Hex8 elements (VTK "hexahedron" node order: the
// face at the cube's low z counter-clockwise seen from +z, then the face above it).
inline TetMesh structured_hex_beam(int nx, int ny, int nz, double lx, double ly, double lz) {
  TetMesh m = structured_tet_beam(nx, ny, nz, lx, ly, lz);  // the same nodes
  auto id = [&](int i, int j, int k) { return (i * (ny + 1) + j) * (nz + 1) + k; };
  m.cells.resize(nx * ny * nz, 8);
  int e = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k, ++e) {
        const std::array<int, 8> corner = Hex8::grid_cube(id, i, j, k);
        for (int a = 0; a < 8; ++a) m.cells(e, a) = corner[a];
      }
  return m;
}

// TetGen .node/.ele pair (path of either file; 0- or 1-based as the .node file says).
inline TetMesh read_tetgen(const std::string& path) {
  const std::string stem = path.substr(0, path.find_last_of('.'));
  auto open = [](const std::string& p) {
    std::ifstream in(p);
    if (!in) throw InvalidInput("cannot open mesh file " + p);
    return in;
  };
  auto next_line = [](std::ifstream& in) {
    std::string line;
    while (std::getline(in, line)) {
      const auto hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      if (line.find_first_not_of(" \t\r") != std::string::npos) return std::istringstream(line);
    }
    throw InvalidInput("mesh file ended early");
  };
  TetMesh m;
  auto node_in = open(stem + ".node");
  int n, dim, attrs, marker;
  next_line(node_in) >> n >> dim >> attrs >> marker;
  m.points.resize(3, n);
  int base = 0;
  for (int i = 0; i < n; ++i) {
    int idx;
    auto line = next_line(node_in);
    line >> idx >> m.points(0, i) >> m.points(1, i) >> m.points(2, i);
    if (i == 0) base = idx;
  }
  auto ele_in = open(stem + ".ele");
  int ne, per;
  next_line(ele_in) >> ne >> per;
  if (per != 4) throw InvalidInput("only 4-node tets are supported in .ele files");
  m.cells.resize(ne, 4);
  for (int e = 0; e < ne; ++e) {
    int idx;
    auto line = next_line(ele_in);
    line >> idx;
    for (int a = 0; a < 4; ++a) {
      line >> m.cells(e, a);
      m.cells(e, a) -= base;
    }
  }
  return m;
}

}  // namespace corotate::bench
