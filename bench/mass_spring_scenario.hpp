// corotate_bench --scenario mass_spring: times explicit mass-spring stepping without Python.
//
// Bodies: cloth 64x64 and 256x256 particles (1 x 1 m, E = 0.5 MPa, 1 mm, 200 kg/m^3, beta = 1e-5, pinned
// at two corners, the `corotate scenes` cloth) and cube lattices 20^3 and 40^3 cells
// (0.5 m, E = 200 kPa, 1000 kg/m^3, beta = 1e-4, bottom layer pinned). Gravity; frames of 1/60 s
// sub-stepped at 0.9 x the conservative (fixed-policy) critical step; velocity Verlet.
// Bodies over 200,000 springs run frames/10 frames (at least 3). Prints springs, substeps per frame, median ms per
// frame and per substep, springs per second (springs x substeps / wall time), the real-time ratio, the time of one
// dt_crit estimate, and how much larger the online (current-configuration) step is at rest.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "corotate/models/spring_builders.hpp"
#include "corotate/simulation.hpp"

namespace corotate::bench {

inline int mass_spring_main(int argc, char** argv) {
  int frames = 30;
  IntegratorKind scheme = IntegratorKind::Verlet;
  for (int a = 0; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--frames" && a + 1 < argc) frames = std::stoi(argv[++a]);
    else if (arg == "--integrator" && a + 1 < argc) {
      scheme = integrator_from_name(argv[++a]);
      if (!is_explicit(scheme)) throw InvalidInput("--integrator: verlet or symplectic_euler");
    } else if (arg == "--help" || arg == "-h") {
      std::puts(
          "usage: corotate_bench --scenario mass_spring [--frames N (default 30)] [--integrator "
          "verlet|symplectic_euler]");
      return 0;
    } else throw InvalidInput("unknown option " + arg + " for --scenario mass_spring");
  }
  using clock_type = std::chrono::steady_clock;
  struct Case {
    std::string label;
    SpringSystem system;
    std::vector<Index> pinned;
  };
  std::vector<Case> cases;
  for (int n : {64, 256}) {
    ClothSettings c;
    c.nx = c.ny = n;
    c.youngs_modulus = 5e5;
    c.thickness = 1e-3;
    c.density = 200.0;
    c.bending = 0.01;
    c.beta = 1e-5;
    cases.push_back({"cloth " + std::to_string(n) + "x" + std::to_string(n),
                     cloth_grid(c),
                     {Index(n) * (n - 1), Index(n) * n - 1}});
  }
  for (int n : {20, 40}) {
    LatticeSettings l;
    l.nx = l.ny = l.nz = n;
    l.size_x = l.size_y = l.size_z = 0.5;
    l.youngs_modulus = 2e5;
    l.density = 1000.0;
    l.beta = 1e-4;
    Case c{"lattice " + std::to_string(n) + "^3", cube_lattice(l), {}};
    for (Index i = 0; i < c.system.nodes.cols(); ++i)
      if (c.system.nodes(2, i) == 0.0) c.pinned.push_back(i);
    cases.push_back(std::move(c));
  }
  std::printf(
      "scenario: mass-spring, %s, frames of 1/60 s at 0.9 x the fixed-policy critical step, gravity, %d frames, one "
      "thread\n",
      integrator_name(scheme), frames);
  std::printf("%-16s %8s %9s %9s %9s %9s %8s %10s %9s %9s %9s\n", "body", "nodes", "springs", "precmp_ms", "substeps",
              "ms/frame", "us/sub", "Msprings/s", "rt_ratio", "est_ms", "online_x");
  for (auto& c : cases) {
    const auto t0 = clock_type::now();
    const Index springs = static_cast<Index>(c.system.springs.size()), nodes = c.system.nodes.cols();
    IntegratorSettings s;
    s.kind = scheme;
    s.time_step = 1.0 / 60.0;
    Simulation sim(std::make_unique<MassSpring>(c.system.nodes, std::move(c.system.springs), c.system.masses), s);
    sim.set_fixed_nodes(c.pinned);
    sim.set_gravity(Vec3(0, 0, -9.81));
    const double fixed_step = sim.stability().critical_step;
    const double precompute_ms = std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
    const auto t1 = clock_type::now();
    const double online_step = sim.estimate_stability(false).critical_step;
    const double estimate_ms = std::chrono::duration<double, std::milli>(clock_type::now() - t1).count();
    sim.reset_stats();
    // Large bodies take seconds per frame: fewer frames there (at least 3; the median is kept).
    const int n_frames = springs > 200000 ? std::max(3, frames / 10) : frames;
    std::vector<double> frame_ms;
    for (int f = 0; f < n_frames; ++f) {
      const auto tf = clock_type::now();
      sim.step(1);
      frame_ms.push_back(std::chrono::duration<double, std::milli>(clock_type::now() - tf).count());
    }
    std::sort(frame_ms.begin(), frame_ms.end());
    const auto& st = sim.stats();
    const double substeps = double(st.substeps) / st.steps;
    const double median = frame_ms[frame_ms.size() / 2];
    std::printf("%-16s %8ld %9ld %9.1f %9.0f %9.2f %8.2f %10.1f %9.2f %9.2f %9.2f\n", c.label.c_str(),
                static_cast<long>(nodes), static_cast<long>(springs), precompute_ms, substeps, median,
                1e3 * median / substeps, springs * substeps / (median * 1e-3) * 1e-6, (1.0 / 60.0) / (median * 1e-3),
                estimate_ms, online_step / fixed_step);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace corotate::bench
