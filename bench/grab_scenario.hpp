// corotate_bench --scenario grab: what a grab and a release cost in frame time (issue 9).
//
// Body: the standard beam (bench/README.md; clamped at x = 0, gravity, corotate's default
// PCG, frames of 5 steps of 0.01 s) or a user mesh (--mesh, see beam_scenario.hpp's read_mesh). A user grabs the node
// at the top of the free end, drags it up by 2 cm per frame for 10 frames and lets go; five such cycles, each after 10
// undisturbed frames, following 30 warm-up frames. Three ways to grab:
//   attach        Simulation::attach a spring of stiffness k at the node's position, move its
//                 target every frame, detach (fem/attachments.hpp);
//   fix           add the node to the fixed set and prescribe its velocity; release by
//                 restoring the fixed set (the solver keeps its preconditioner);
//   fix_rebuild   the same, with the linear solver rebuilt after each change of the fixed
//                 set: what set_fixed_nodes did before (solver reset).
// Prints per mode the median frame without interaction, the median and worst frame right
// after a grab (the grab call included) and right after a release, the median drag frame,
// the worst of those as a multiple of the median undisturbed frame, and CG iterations per
// step while undisturbed and while dragging. Frame times are CPU time (see cpu_ms).
#pragma once

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "beam_scenario.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/pcg.hpp"

namespace corotate::bench {

struct GrabResult {
  std::vector<double> normal, grab, drag, release;  // frame times [ms]
  double normal_iterations = 0, drag_iterations = 0;
};

inline double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// CPU time of this (single-threaded) process [ms]: on a shared machine wall time swings by
// 2x between identical frames when other jobs compete for the cores; CPU time does not.
inline double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

inline GrabResult run_grab(const TetMesh& mesh, const std::string& mode, double stiffness, int cycles) {
  const int steps_per_frame = 5;
  const double dt = 0.01, lift_per_frame = 0.02;
  IntegratorSettings settings;
  settings.time_step = dt;
  Simulation sim(make_model("corotational", mesh.cell_type, mesh.points, mesh.cells, Material{1e7, 0.3, 1000.0}),
                 settings, std::make_unique<PCG>());
  const double x_min = mesh.points.row(0).minCoeff();
  std::vector<Index> clamped;
  Index grabbed = 0;
  for (Index i = 0; i < mesh.points.cols(); ++i) {
    if (mesh.points(0, i) <= x_min + 1e-9) clamped.push_back(i);
    // The highest node of the free end.
    const auto key = [&](Index j) { return std::make_pair(mesh.points(0, j), mesh.points(2, j)); };
    if (key(i) > key(grabbed)) grabbed = i;
  }
  sim.set_fixed_nodes(clamped);
  sim.set_gravity(Vec3(0, 0, -9.81));

  GrabResult r;
  long long iterations_before = 0;
  auto frame = [&](const auto& before_step) {
    const double t0 = cpu_ms();
    before_step();
    iterations_before = sim.stats().total_iterations;
    sim.step(steps_per_frame);
    return cpu_ms() - t0;
  };
  auto iterations_per_step = [&]() {
    return double(sim.stats().total_iterations - iterations_before) / steps_per_frame;
  };
  const auto nothing = [] {};
  auto set_fixed = [&](bool with_grabbed) {
    std::vector<Index> fixed = clamped;
    if (with_grabbed) fixed.push_back(grabbed);
    sim.set_fixed_nodes(fixed);
    if (mode == "fix_rebuild") sim.set_solver(std::make_unique<PCG>());
  };
  const Vec3 lift_velocity(0, 0, lift_per_frame / (steps_per_frame * dt));
  for (int f = 0; f < 30; ++f) frame(nothing);
  for (int c = 0; c < cycles; ++c) {
    for (int f = 0; f < 10; ++f) {
      r.normal.push_back(frame(nothing));
      r.normal_iterations += iterations_per_step() / (10.0 * cycles);
    }
    Vec3 target = sim.positions().col(grabbed);
    r.grab.push_back(frame([&] {
      if (mode == "attach") {
        sim.attach({grabbed}, target, Vec::Constant(1, stiffness));
      } else {
        set_fixed(true);
        sim.velocities().col(grabbed) = lift_velocity;
      }
    }));
    for (int f = 1; f < 10; ++f) {
      r.drag.push_back(frame([&] {
        target.z() += lift_per_frame;
        if (mode == "attach") sim.move_attachments({grabbed}, target);
      }));
      r.drag_iterations += iterations_per_step() / (9.0 * cycles);
    }
    r.release.push_back(frame([&] {
      if (mode == "attach") sim.detach({grabbed});
      else set_fixed(false);
    }));
    for (int f = 1; f < 10; ++f) frame(nothing);
  }
  return r;
}

inline int grab_main(int argc, char** argv) {
  std::vector<int> sizes = {2, 4};
  std::string mesh_path;
  double stiffness = 1e6;
  int cycles = 5;
  for (int a = 0; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--sizes" && a + 1 < argc) sizes = parse_sizes(argv[++a]);
    else if (arg == "--mesh" && a + 1 < argc) mesh_path = argv[++a];
    else if (arg == "--stiffness" && a + 1 < argc) stiffness = std::stod(argv[++a]);
    else if (arg == "--cycles" && a + 1 < argc) cycles = std::stoi(argv[++a]);
    else if (arg == "--help" || arg == "-h") {
      std::puts(
          "usage: corotate_bench --scenario grab [--sizes 2,4 (beam refinements)] [--mesh FILE]\n"
          "                      [--stiffness K (N/m, default 1e6)] [--cycles N (default 5)]\n"
          "Frame times (5 steps of 0.01 s, default PCG) right after grabbing and releasing the top node\n"
          "of the free end: by an attachment spring, by fixing it, and by fixing with a solver rebuild.");
      return 0;
    } else throw InvalidInput("unknown option " + arg + " for --scenario grab");
  }
  std::vector<std::pair<std::string, TetMesh>> meshes;
  if (!mesh_path.empty())
    meshes.emplace_back(mesh_path.substr(mesh_path.find_last_of("/\\") + 1), read_mesh(mesh_path));
  else
    for (int s : sizes)
      meshes.emplace_back("beam " + std::to_string(10 * s) + "x" + std::to_string(2 * s) + "x" + std::to_string(2 * s),
                          structured_beam("tet4", 10 * s, 2 * s, 2 * s, 5.0, 1.0, 1.0));
  std::printf(
      "scenario: grab and drag the top node of the free end, corotational tets, E=1e7, default PCG, frames of 5 x "
      "0.01 s, %d cycles, attachment k=%g N/m, one thread, CPU ms per frame\n",
      cycles, stiffness);
  std::printf("%-16s %7s %-12s %8s %8s %8s %8s %8s %8s %8s %7s %7s\n", "mesh", "tets", "mode", "normal", "grab_med",
              "grab_max", "drag", "rel_med", "rel_max", "worst/n", "it_norm", "it_drag");
  for (const auto& [label, mesh] : meshes)
    for (const std::string mode : {"attach", "fix", "fix_rebuild"}) {
      const GrabResult r = run_grab(mesh, mode, stiffness, cycles);
      const double normal = median_of(r.normal);
      const double worst = std::max(
          {*std::max_element(r.grab.begin(), r.grab.end()), *std::max_element(r.release.begin(), r.release.end())});
      std::printf("%-16s %7ld %-12s %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %7.2f %7.2f\n", label.c_str(),
                  static_cast<long>(mesh.cells.rows()), mode.c_str(), normal, median_of(r.grab),
                  *std::max_element(r.grab.begin(), r.grab.end()), median_of(r.drag), median_of(r.release),
                  *std::max_element(r.release.begin(), r.release.end()), worst / normal, r.normal_iterations,
                  r.drag_iterations);
      std::fflush(stdout);
    }
  return 0;
}

}  // namespace corotate::bench
