// Topology builders for mass-spring systems: cloth grid (paper Fig. 1), cube lattice
// (Fig. 2) and springs on the elements of any tet or hex mesh; each returns nodes, springs
// and masses, plus display cells (quads / hexahedra / the mesh) for output.
//
// Stiffness from a Young's modulus E (the paper notes that a spring network has no unique
// stiffness; this is the rule corotate uses). Each cell (cloth square, lattice cube, mesh
// element) of volume V (cloth: area x thickness) adds to each of its springs s
//     k_s += alpha_s E V / l_s^2,
// and a spring shared by several cells sums their shares. Under a homogeneous small strain
// eps a spring stretches by l_s (n_s . eps n_s), so the network's energy is
//     sum over cells of  E V / 2  sum_s alpha_s (n_s . eps n_s)^2,
// i.e. every cell carries an elasticity tensor E sum_s alpha_s n n n n independent of its
// size: refining a body keeps its small-strain stiffness for every homogeneous strain, at
// the boundary too. The weights alpha are chosen so that this tensor is
//   - cube lattice (cubic cells; edges, face and room diagonals, alpha = 0.16, 0.16, 0.54):
//     exactly isotropic with Young's modulus E and Poisson ratio 1/4;
//   - cloth (square cells; structural 3/8, shear 3/4 per cell): an isotropic membrane with
//     in-plane Young's modulus E (stiffness E t per unit width) and Poisson ratio 1/3.
// 1/4 (3D) and 1/3 (2D) are the only Poisson ratios a network of central springs on a
// lattice can have (the Cauchy relations), so no rule can do better for nu != 1/4.
// Mesh elements get the weights that make sum_s alpha_s = 6 (tets: 1 per edge; hexes: the
// lattice weights with diagonals, 1/2 per edge without): the energy of any uniform
// dilation equals that of the continuum with bulk modulus K = 2E/3 (= E / (3 (1 - 2 nu))
// at nu = 1/4) for any element shape; the lattice and cloth rules satisfy the same.
// Hexes without diagonals have zero-energy shear modes (a cube of edges is a mechanism).
// Cloth bending springs (every second node) add k_bend = bending E t each, on top of the
// membrane rule (in-plane they stiffen the membrane by a relative O(bending)).
//
// Damping: d_s = beta k_s, the spring form of Rayleigh stiffness damping beta K, so a mode
// of angular frequency w gets the damping ratio beta w / 2 at every resolution.
// Masses: density x cell volume, shared equally by the cell's nodes.
#pragma once

#include <string>
#include <vector>

#include "corotate/models/mass_spring.hpp"

namespace corotate {

struct SpringSystem {
  Nodes nodes;                   // 3 x n rest positions
  std::vector<Spring> springs;   // with k, d and l0 (= rest distance) set
  std::vector<int> kinds;  // per spring: 0 structural / edge, 1 shear / face diagonal, 2 bending / room diagonal
  Vec masses;  // n point masses [kg]
  Connectivity cells;  // display cells, one row per cell
  std::string cell_type;  // "quad", "hexahedron" or "tetra" (meshio names)
};

struct ClothSettings {
  int nx = 32, ny = 32;  // particles along x and y (>= 2 each)
  double width = 1.0, height = 1.0;  // extent in x and y [m]; the cloth lies in z = 0
  double youngs_modulus = 1e6;  // E [Pa]
  double thickness = 1e-3;  // t [m]
  double density = 1000.0;  // [kg/m^3]
  double bending = 0.01;  // k_bend / (E t); 0 = no bending springs
  double beta = 0.0;  // damping time [s]: d = beta k
};

struct LatticeSettings {
  int nx = 4, ny = 4, nz = 4;  // cubes along x, y, z (>= 1 each)
  double size_x = 1.0, size_y = 1.0, size_z = 1.0;  // extent [m], from the origin
  double youngs_modulus = 1e6, density = 1000.0, beta = 0.0;
};

// Cloth: node (i, j) (i along x) has index j * nx + i; structural springs to the right and
// upper neighbours, both diagonals of each cell, bending springs two nodes away.
SpringSystem cloth_grid(const ClothSettings& s);
// Cube lattice: node (i, j, k) has index (k * (ny + 1) + j) * (nx + 1) + i.
SpringSystem cube_lattice(const LatticeSettings& s);
// Springs on the edges of each element (cell_type "tetra" or "hexahedron"; face and room
// diagonals of hexes when diagonals is true), rule above with E, masses from density.
SpringSystem springs_from_mesh(const Nodes& points, const Connectivity& cells, const std::string& cell_type,
                               double youngs_modulus, double density, double beta, bool diagonals);

}  // namespace corotate
