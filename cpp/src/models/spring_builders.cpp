#include "corotate/models/spring_builders.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "corotate/elements/cell_types.hpp"
#include "corotate/elements/hex8.hpp"
#include "corotate/elements/tet4.hpp"

namespace corotate {

namespace {

// Hexahedron (VTK order) spring sets beyond its edges (Hex8::edges): face and room diagonals.
constexpr int kHexFaceDiagonals[12][2] = {{0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 5}, {1, 4},
                                          {1, 6}, {2, 5}, {2, 7}, {3, 6}, {3, 4}, {0, 7}};
constexpr int kHexRoomDiagonals[4][2] = {{0, 6}, {1, 7}, {2, 4}, {3, 5}};
// Per-cell weights (see spring_builders.hpp): isotropic E, nu = 1/4 for cubic cells.
constexpr double kLatticeEdge = 0.16, kLatticeFace = 0.16, kLatticeRoom = 0.54;

// Springs collected cell by cell; a pair shared by several cells sums their stiffness.
class SpringAccumulator {
 public:
  explicit SpringAccumulator(const Nodes& nodes) : nodes_(nodes) {}

  // Adds the share weight * E V / l^2 of one cell to spring (a, b).
  void add_share(int a, int b, double weight_EV, int kind) {
    const double l2 = (nodes_.col(b) - nodes_.col(a)).squaredNorm();
    add(a, b, weight_EV / l2, kind);
  }
  void add(int a, int b, double k, int kind) {
    const long long key = (static_cast<long long>(std::min(a, b)) << 32) | static_cast<long long>(std::max(a, b));
    auto [it, inserted] = index_.try_emplace(key, static_cast<int>(springs_.size()));
    if (inserted) {
      Spring s;
      s.i = std::min(a, b);
      s.j = std::max(a, b);
      springs_.push_back(s);
      kinds_.push_back(kind);
    }
    springs_[it->second].stiffness += k;
  }
  void finish(double beta, SpringSystem& out) {
    for (Spring& s : springs_) {
      s.rest_length = (nodes_.col(s.j) - nodes_.col(s.i)).norm();
      s.damping = beta * s.stiffness;
    }
    out.springs = std::move(springs_);
    out.kinds = std::move(kinds_);
  }

 private:
  const Nodes& nodes_;
  std::unordered_map<long long, int> index_;
  std::vector<Spring> springs_;
  std::vector<int> kinds_;
};

void check_common(double E, double density, double beta) {
  if (!(E > 0) || !std::isfinite(E))
    throw InvalidInput("Young's modulus must be positive and finite, got " + std::to_string(E));
  if (!(density > 0) || !std::isfinite(density))
    throw InvalidInput("density must be positive and finite, got " + std::to_string(density));
  if (!(beta >= 0) || !std::isfinite(beta))
    throw InvalidInput("damping time beta must be >= 0 and finite, got " + std::to_string(beta));
}

// Springs and masses of one hexahedron with corner node indices c[0..7] and volume V.
void add_hex(const int* c, double V, double E, double density, bool diagonals, SpringAccumulator& acc, Vec& masses) {
  const double EV = E * V;
  const double edge = diagonals ? kLatticeEdge : 0.5;
  for (const auto& p : Hex8::edges) acc.add_share(c[p[0]], c[p[1]], edge * EV, 0);
  if (diagonals) {
    for (const auto& p : kHexFaceDiagonals) acc.add_share(c[p[0]], c[p[1]], kLatticeFace * EV, 1);
    for (const auto& p : kHexRoomDiagonals) acc.add_share(c[p[0]], c[p[1]], kLatticeRoom * EV, 2);
  }
  for (int a = 0; a < 8; ++a) masses[c[a]] += density * V / 8;
}

}  // namespace

SpringSystem cloth_grid(const ClothSettings& s) {
  if (s.nx < 2 || s.ny < 2)
    throw InvalidInput("a cloth needs at least 2 x 2 particles, got " + std::to_string(s.nx) + " x " +
                       std::to_string(s.ny));
  if (!(s.width > 0) || !(s.height > 0)) throw InvalidInput("cloth width and height must be positive");
  if (!(s.thickness > 0) || !std::isfinite(s.thickness))
    throw InvalidInput("cloth thickness must be positive and finite");
  if (!(s.bending >= 0) || !std::isfinite(s.bending)) throw InvalidInput("cloth bending ratio must be >= 0 and finite");
  check_common(s.youngs_modulus, s.density, s.beta);
  SpringSystem out;
  const int nx = s.nx, ny = s.ny;
  const double dx = s.width / (nx - 1), dy = s.height / (ny - 1);
  auto id = [nx](int i, int j) { return j * nx + i; };
  out.nodes.resize(3, Index(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) out.nodes.col(id(i, j)) = Vec3(i * dx, j * dy, 0.0);
  out.masses = Vec::Zero(out.nodes.cols());
  out.cells.resize(Index(nx - 1) * (ny - 1), 4);
  SpringAccumulator acc(out.nodes);
  const double EV = s.youngs_modulus * dx * dy * s.thickness;
  const double cell_mass = s.density * dx * dy * s.thickness;
  int c = 0;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i, ++c) {
      const int q[4] = {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      for (int a = 0; a < 4; ++a) {
        acc.add_share(q[a], q[(a + 1) % 4], 3.0 / 8.0 * EV, 0);  // structural
        out.cells(c, a) = q[a];
        out.masses[q[a]] += cell_mass / 4;
      }
      acc.add_share(q[0], q[2], 3.0 / 4.0 * EV, 1);  // shear
      acc.add_share(q[1], q[3], 3.0 / 4.0 * EV, 1);
    }
  if (s.bending > 0) {
    const double kb = s.bending * s.youngs_modulus * s.thickness;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (i + 2 < nx) acc.add(id(i, j), id(i + 2, j), kb, 2);
        if (j + 2 < ny) acc.add(id(i, j), id(i, j + 2), kb, 2);
      }
  }
  acc.finish(s.beta, out);
  out.cell_type = "quad";
  return out;
}

SpringSystem cube_lattice(const LatticeSettings& s) {
  if (s.nx < 1 || s.ny < 1 || s.nz < 1) throw InvalidInput("a lattice needs at least one cube along each axis");
  if (!(s.size_x > 0) || !(s.size_y > 0) || !(s.size_z > 0)) throw InvalidInput("lattice size must be positive");
  check_common(s.youngs_modulus, s.density, s.beta);
  SpringSystem out;
  const int nx = s.nx, ny = s.ny, nz = s.nz;
  const double hx = s.size_x / nx, hy = s.size_y / ny, hz = s.size_z / nz;
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  out.nodes.resize(3, Index(nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) out.nodes.col(id(i, j, k)) = Vec3(i * hx, j * hy, k * hz);
  out.masses = Vec::Zero(out.nodes.cols());
  out.cells.resize(Index(nx) * ny * nz, 8);
  SpringAccumulator acc(out.nodes);
  int c = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i, ++c) {
        const std::array<int, 8> h = Hex8::grid_cube(id, i, j, k);
        for (int a = 0; a < 8; ++a) out.cells(c, a) = h[a];
        add_hex(h.data(), hx * hy * hz, s.youngs_modulus, s.density, true, acc, out.masses);
      }
  acc.finish(s.beta, out);
  out.cell_type = "hexahedron";
  return out;
}

SpringSystem springs_from_mesh(const Nodes& points, const Connectivity& cells, const std::string& cell_type,
                               double youngs_modulus, double density, double beta, bool diagonals) {
  check_common(youngs_modulus, density, beta);
  // The spring weights below are derived for linear tets and cubic cells (spring_builders.hpp).
  const bool tet = cell_type == Tet4::name, hex = cell_type == Hex8::name;
  if (!tet && !hex)
    throw InvalidInput(std::string("mass-spring systems from meshes support ") + Tet4::name + " and " + Hex8::name +
                       " cells, not '" + cell_type + "'");
  const Vec volumes = signed_cell_volumes(cell_type, points, cells);  // checks shapes and indices
  const Index n = points.cols();
  SpringSystem out;
  out.nodes = points;
  out.masses = Vec::Zero(n);
  out.cells = cells;
  out.cell_type = cell_type;
  SpringAccumulator acc(out.nodes);
  for (Index e = 0; e < cells.rows(); ++e) {
    const int* c = &cells(e, 0);
    const double V = volumes(e);
    if (!(V > 0)) {
      std::ostringstream msg;
      msg << cell_type << " cell " << e << " has non-positive volume " << V << " (degenerate or inverted)";
      throw InvalidInput(msg.str());
    }
    if (tet) {
      for (const auto& p : Tet4::edges) acc.add_share(c[p[0]], c[p[1]], youngs_modulus * V, 0);
      for (int a = 0; a < 4; ++a) out.masses[c[a]] += density * V / 4;
    } else {
      add_hex(c, V, youngs_modulus, density, diagonals, acc, out.masses);
    }
  }
  for (Index i = 0; i < n; ++i)
    if (out.masses[i] == 0)
      throw InvalidInput("node " + std::to_string(i) + " belongs to no cell (it would have no mass)");
  acc.finish(beta, out);
  return out;
}

}  // namespace corotate
