// corotate_bench --scenario feedback: times one haptic feedback query (feedback/haptic_feedback.hpp)
// without Python: the force on each tool node and the 3k x 3k stiffness dF/dx.
//
// Body: the standard beam (5 x 1 x 1 m, E = 1e7 Pa, nu = 0.3) cut into 35 x 7 x 7 cubes of 6 tets
// (10,290 tets), bent and twisted (every node rotated about x by up to 30 degrees along the beam
// and stretched by 10 %: a large rotation); tool: the 10 nodes nearest the centre of the tip face.
// For each method: 200 queries to warm up, then 5,000 timed one by one; prints the elements
// around the tool and the median and 99th-percentile microseconds per query, on one thread.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "beam_scenario.hpp"
#include "corotate/feedback/haptic_feedback.hpp"

namespace corotate::bench {

inline int feedback_main(int argc, char** argv) {
  int queries = 5000, tool_size = 10;
  for (int a = 0; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--queries" && a + 1 < argc) queries = std::stoi(argv[++a]);
    else if (arg == "--tool" && a + 1 < argc) tool_size = std::stoi(argv[++a]);
    else if (arg == "--help" || arg == "-h") {
      std::puts("usage: corotate_bench --scenario feedback [--queries N (default 5000)] [--tool K (default 10 nodes)]");
      return 0;
    } else throw InvalidInput("unknown option " + arg + " for --scenario feedback");
  }
  using clock_type = std::chrono::steady_clock;
  const TetMesh mesh = structured_beam("tet4", 35, 7, 7, 5.0, 1.0, 1.0);
  const Index n = mesh.points.cols();
  Nodes x(3, n);
  for (Index i = 0; i < n; ++i) {
    const Vec3 p = mesh.points.col(i);
    const double angle = 0.5236 * p.x() / 5.0;  // up to 30 degrees at the tip
    x.col(i) = Vec3(1.1 * p.x(), 0.5 + std::cos(angle) * (p.y() - 0.5) - std::sin(angle) * (p.z() - 0.5),
                    0.5 + std::sin(angle) * (p.y() - 0.5) + std::cos(angle) * (p.z() - 0.5));
  }
  std::vector<std::pair<double, Index>> by_distance;
  for (Index i = 0; i < n; ++i) by_distance.emplace_back((mesh.points.col(i) - Vec3(5.0, 0.5, 0.5)).norm(), i);
  std::partial_sort(by_distance.begin(), by_distance.begin() + tool_size, by_distance.end());
  std::vector<Index> tool;
  for (int k = 0; k < tool_size; ++k) tool.push_back(by_distance[k].second);

  std::printf("scenario: feedback query, beam of %ld tets, tool of %d nodes, large rotation, one thread\n",
              static_cast<long>(mesh.cells.rows()), tool_size);
  std::printf("%-14s %9s %10s %10s %12s\n", "method", "elements", "median_us", "p99_us", "|F| [N]");
  const Material material{1e7, 0.3, 1000.0};
  for (const auto& name : feedback_method_names()) {
    HapticFeedback feedback(mesh.cell_type, mesh.points, mesh.cells, material, tool, feedback_method_from_name(name));
    Nodes forces;
    Eigen::MatrixXd stiffness;
    for (int q = 0; q < 200; ++q) feedback.query(x, forces, stiffness);
    std::vector<double> us(queries);
    for (int q = 0; q < queries; ++q) {
      const auto t0 = clock_type::now();
      feedback.query(x, forces, stiffness);
      us[q] = std::chrono::duration<double, std::micro>(clock_type::now() - t0).count();
    }
    std::sort(us.begin(), us.end());
    std::printf("%-14s %9ld %10.2f %10.2f %12.4g\n", name.c_str(), static_cast<long>(feedback.num_elements()),
                us[us.size() / 2], us[us.size() * 99 / 100], forces.rowwise().sum().norm());
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace corotate::bench
