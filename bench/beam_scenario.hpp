// The standard benchmark scenario (bench/README.md): a 5 x 1 x 1 m beam along x, clamped at
// x = 0, sagging under gravity from rest (of any solid element); and user meshes handed over
// as text by `corotate bench --mesh FILE`.
#pragma once

#include <array>
#include <fstream>
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

// A mesh in write_mesh's text form, as `corotate bench --mesh FILE` hands it over after
// reading FILE (any format) with corotate.read_mesh: the benchmark parses no mesh format of
// its own. The node and cell counts are checked against the header.
inline TetMesh read_mesh(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput("cannot open mesh file " + path);
  Index n = 0, m = 0, k = 0;
  TetMesh mesh;
  if (!(in >> n >> m >> k) || n < 1 || m < 1 || k < 1) throw InvalidInput(path + ": not a mesh written by write_mesh");
  mesh.points.resize(3, n);
  mesh.cells.resize(m, k);
  for (Index i = 0; i < n; ++i) in >> mesh.points(0, i) >> mesh.points(1, i) >> mesh.points(2, i);
  for (Index e = 0; e < m; ++e)
    for (Index a = 0; a < k; ++a) in >> mesh.cells(e, a);
  if (!(in >> mesh.cell_type))
    throw InvalidInput(path + " ended early (expected " + std::to_string(n) + " nodes and " + std::to_string(m) +
                       " cells)");
  return mesh;
}

}  // namespace corotate::bench
