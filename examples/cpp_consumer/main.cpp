// A soft 5 x 1 x 1 m co-rotational tet beam, clamped at x = 0, falls for 50 steps under gravity.
// Prints the mean tip displacement; exits nonzero unless it is finite and downwards.
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

#include "corotate/models/model_factory.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/pcg.hpp"
#include "corotate/version.hpp"

using namespace corotate;

int main() {
  const int nx = 10, ny = 2, nz = 2;  // cubes of 0.5 m, 6 tets each around the cube diagonal
  auto id = [&](int i, int j, int k) { return (i * (ny + 1) + j) * (nz + 1) + k; };
  Nodes points(3, (nx + 1) * (ny + 1) * (nz + 1));
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j)
      for (int k = 0; k <= nz; ++k) points.col(id(i, j, k)) = 0.5 * Vec3(i, j, k);
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  Connectivity cells(6 * nx * ny * nz, 4);
  int e = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        for (const auto& p : perms) {  // walk from corner (i, j, k) to the opposite one
          int c[3] = {i, j, k}, tet[4] = {id(i, j, k), 0, 0, 0};
          for (int s = 0; s < 3; ++s) ++c[p[s]], tet[s + 1] = id(c[0], c[1], c[2]);
          Mat3 D;
          for (int s = 0; s < 3; ++s) D.col(s) = points.col(tet[s + 1]) - points.col(tet[0]);
          if (D.determinant() < 0) std::swap(tet[1], tet[2]);  // positive orientation
          for (int a = 0; a < 4; ++a) cells(e, a) = tet[a];
          ++e;
        }
  const Material material{1e6, 0.3, 1000.0};
  IntegratorSettings implicit_euler;  // linearised implicit Euler, dt = 0.01 s
  PCGSettings pcg;  // solved to 1e-6 (the default, 1e-2, is tuned for speed)
  pcg.tolerance = 1e-6;
  pcg.max_iterations = 200;
  Simulation sim(make_model("corotational", "tetra", points, cells, material), implicit_euler,
                 std::make_unique<PCG>(pcg));
  std::vector<Index> fixed, tip;
  for (Index n = 0; n < points.cols(); ++n) {
    if (points(0, n) == 0) fixed.push_back(n);
    if (points(0, n) == 0.5 * nx) tip.push_back(n);
  }
  sim.set_fixed_nodes(fixed);
  sim.set_gravity(Vec3(0, 0, -9.81));
  sim.step(50);
  Vec3 displacement = Vec3::Zero();
  for (Index n : tip) displacement += (sim.positions().col(n) - points.col(n)) / double(tip.size());
  std::printf("corotate %s: %ld tets, tip displacement after %.2f s: (%.4f, %.4f, %.4f) m\n", COROTATE_VERSION_STRING,
              static_cast<long>(cells.rows()), sim.time(), displacement.x(), displacement.y(), displacement.z());
  return displacement.allFinite() && displacement.z() < 0 ? 0 : 1;
}
