// corotate_bench --scenario embedding: times the embedded render surface
// (embedding/surface_embedding.hpp) without Python, on one thread.
//
// Per frame: a body of 10 x 3 x 4 unit cubes of 6 tets (720 tets, the paper's dog has 700)
// carrying 12,500 surface vertices (uniformly random inside it; 25,000 triangles joining
// neighbouring vertices in index order): the median microseconds of the position update, the
// area-weighted normals and the element-rotated normals over 2,000 repetitions, each on a
// bent and twisted configuration.
// Coupling: 1,000,000 random vertices (5 % of them up to half an element outside) to a beam
// of about 100,000 tets: seconds for the whole coupling, grid included.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "beam_scenario.hpp"
#include "corotate/embedding/surface_embedding.hpp"

namespace corotate::bench {

// n random points in the box [0, size]; a fraction `outside` of them pushed up to `margin` beyond z = size.z.
inline Nodes random_vertices(Index n, const Vec3& size, double outside, double margin, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Nodes p(3, n);
  for (Index j = 0; j < n; ++j) {
    p.col(j) = Vec3(u(rng), u(rng), u(rng)).cwiseProduct(size);
    if (u(rng) < outside) p(2, j) = size.z() + margin * u(rng);
  }
  return p;
}

inline int embedding_main(int argc, char** argv) {
  Index vertices = 12500, coupling_vertices = 1000000;
  int repeats = 2000, coupling_cells = 100000;
  for (int a = 0; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--vertices" && a + 1 < argc) vertices = std::stol(argv[++a]);
    else if (arg == "--repeats" && a + 1 < argc) repeats = std::stoi(argv[++a]);
    else if (arg == "--coupling-vertices" && a + 1 < argc) coupling_vertices = std::stol(argv[++a]);
    else if (arg == "--coupling-cells" && a + 1 < argc) coupling_cells = std::stoi(argv[++a]);
    else if (arg == "--help" || arg == "-h") {
      std::puts(
          "usage: corotate_bench --scenario embedding [--vertices N (default 12500)] [--repeats N (2000)]\n"
          "       [--coupling-vertices N (1000000)] [--coupling-cells N (about 100000 tets)]");
      return 0;
    } else throw InvalidInput("unknown option " + arg + " for --scenario embedding");
  }
  using clock_type = std::chrono::steady_clock;
  const auto seconds_since = [](clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
  };

  // Per frame.
  const TetMesh body = structured_beam("tet4", 10, 3, 4, 10.0, 3.0, 4.0);
  const Nodes surface = random_vertices(vertices, Vec3(10, 3, 4), 0.0, 0.0, 7);
  Connectivity triangles(2 * vertices, 3);
  for (Index t = 0; t < triangles.rows(); ++t)
    for (int c = 0; c < 3; ++c) triangles(t, c) = int((t / 2 + c + t % 2) % vertices);
  auto t0 = clock_type::now();
  SurfaceEmbedding embedding(body.cell_type, body.points, body.cells, surface, triangles);
  const double couple_ms = 1e3 * seconds_since(t0);
  Nodes x(3, body.points.cols()), y(3, vertices), normals(3, vertices);
  for (Index i = 0; i < x.cols(); ++i) {
    const Vec3 p = body.points.col(i);
    const double bend = 0.05 * p.x(), twist = 0.04 * p.x();
    x.col(i) = Vec3(std::sin(bend) * (p.z() + 10), std::cos(twist) * p.y() - std::sin(twist) * p.z(),
                    std::cos(bend) * (p.z() + 10) + std::sin(twist) * p.y());
  }
  const auto median_us = [&](auto&& work) {
    std::vector<double> us(repeats);
    for (int r = 0; r < 50; ++r) work();
    for (int r = 0; r < repeats; ++r) {
      const auto s = clock_type::now();
      work();
      us[r] = 1e6 * seconds_since(s);
    }
    std::nth_element(us.begin(), us.begin() + repeats / 2, us.end());
    return us[repeats / 2];
  };
  const double embed_us = median_us([&] { embedding.embed(x, y); });
  const double normals_us = median_us([&] { embedding.vertex_normals(y, normals); });
  const double rotated_us = median_us([&] { embedding.rotated_normals(x, normals); });
  std::printf("scenario: embedding, one thread\n");
  std::printf("per frame: %ld tets, %ld vertices, %ld triangles (coupled in %.1f ms)\n",
              static_cast<long>(body.cells.rows()), static_cast<long>(vertices), static_cast<long>(triangles.rows()),
              couple_ms);
  std::printf("  positions          median %8.1f us\n", embed_us);
  std::printf("  area normals       median %8.1f us\n", normals_us);
  std::printf("  rotated normals    median %8.1f us\n", rotated_us);
  std::fflush(stdout);

  // Coupling: cubes of 6 tets, n x n/2 x n/2 cubes with 6 n^3 / 4 ~ coupling_cells.
  const int n = std::max(2, int(std::lround(std::cbrt(coupling_cells / 1.5))));
  const TetMesh big = structured_beam("tet4", n, n / 2, n / 2, 2.0 * n, 1.0 * n, 1.0 * n);
  const Nodes many = random_vertices(coupling_vertices, Vec3(2.0 * n, 1.0 * n, 1.0 * n), 0.05, 0.5, 11);
  t0 = clock_type::now();
  const SurfaceEmbedding coupled(big.cell_type, big.points, big.cells, many, Connectivity(0, 3));
  const double coupling_s = seconds_since(t0);
  std::printf("coupling: %ld vertices to %ld tets in %.2f s (%ld outside, farthest %.2f element sizes)\n",
              static_cast<long>(coupling_vertices), static_cast<long>(big.cells.rows()), coupling_s,
              static_cast<long>(coupled.report().outside), coupled.report().max_outside_distance);
  return 0;
}

}  // namespace corotate::bench
