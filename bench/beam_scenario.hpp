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
#include "corotate/meshes/structured_box.hpp"

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

// A benchmark mesh: points, cells and their cell type (the generator's, or "tetra" from TetGen).
using TetMesh = StructuredMesh;

// The beam of nx x ny x nz cuboids over [0, lx] x [0, ly] x [0, lz] of the solid element
// named by its generator name ("tet4", "hex8", ...): corotate.beam's mesh, node for node
// (the library's one structured generator, meshes/structured_box.hpp).
inline TetMesh structured_beam(const std::string& element, int nx, int ny, int nz, double lx, double ly, double lz) {
  return structured_box(element, {nx, ny, nz}, Vec3(lx, ly, lz));
}

// The mesh as text: "n m k", n lines of x y z, m lines of k node indices, the cell type; the
// check that the benchmark's beam is corotate.beam's (tests/test_bench_mesh.py).
inline void write_mesh(const std::string& path, const TetMesh& mesh) {
  std::ofstream out(path);
  if (!out) throw InvalidInput("cannot write " + path);
  out.precision(17);
  out << mesh.points.cols() << ' ' << mesh.cells.rows() << ' ' << mesh.cells.cols() << '\n';
  for (Index i = 0; i < mesh.points.cols(); ++i)
    out << mesh.points(0, i) << ' ' << mesh.points(1, i) << ' ' << mesh.points(2, i) << '\n';
  for (Index e = 0; e < mesh.cells.rows(); ++e) {
    for (Index a = 0; a < mesh.cells.cols(); ++a) out << (a ? " " : "") << mesh.cells(e, a);
    out << '\n';
  }
  out << mesh.cell_type << '\n';
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
  m.cell_type = "tetra";
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
