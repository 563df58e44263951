// corotate_bench: times the co-rotational implicit step without Python.
//
// For each mesh it builds the body, computes a converged reference trajectory, then runs
// each solver configuration and prints precompute time, median ms per step (split into
// rotations, assembly and solve), CG iterations per step, the real-time ratio and the mean
// tip z-displacement with its deviation from the reference. See bench/README.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#ifdef __GLIBC__
#include <malloc.h>
#include <unistd.h>
#endif
#include <string>
#include <vector>

#include "beam_scenario.hpp"
#include "corotate/build_info.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/parallel.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"
#include "embedding_scenario.hpp"
#include "feedback_scenario.hpp"
#include "grab_scenario.hpp"
#include "mass_spring_scenario.hpp"
#include "products_scenario.hpp"
#include "rotation_scenario.hpp"

using namespace corotate;
using clock_type = std::chrono::steady_clock;

namespace {

struct Config {
  std::string name;
  std::string solver;  // "pcg" or "direct"
  PCGSettings pcg;
  // IntegratorSettings::matrix_reuse_angle; the paper's configurations and the reference
  // assemble at every step (0), the others take --reuse-angle or the library's default.
  double reuse_angle = IntegratorSettings{}.matrix_reuse_angle;
};

struct Options {
  std::vector<int> sizes = {1, 2, 4, 8};  // refinement factors: 10x2x2 cubes times this
  std::string mesh_path;
  int steps = 100;
  double dt = 0.01;
  bool lumped = false;
  std::string element = "tet4";  // --element: the beam's element (a generator name, structured_box.hpp)
  std::string write_mesh;        // --write-mesh FILE: write the beam's mesh and stop
  bool checks = true;  // the loud-failure checks (simulation.hpp); --no-checks: failure policy Ignore
  SparseCholesky::Backend direct = SparseCholesky::Backend::Auto;  // --direct eigen|cholmod
  bool reference = true;  // --no-reference: skip the converged run (timing only; dev is not printed)
  bool trace = false;  // --trace: one line per step (tip, energy, residual, checks) after each run
  std::vector<std::string> configs = {"paper", "default"};
  PCGSettings custom;  // the 'custom' configuration, set by --preconditioner, --tolerance, --cap, --cold
  double reuse_angle = IntegratorSettings{}.matrix_reuse_angle;  // --reuse-angle
};

struct RunResult {
  double precompute_ms = 0, first_step_ms = 0, median_ms = 0, assembly_ms = 0, solve_ms = 0;
  double iterations = 0, real_time_ratio = 0, tip_z = 0;
  int max_iterations = 0;
  long long stalled_steps = 0, energy_growth_steps = 0;  // loud failures the checks counted
  double bytes_per_element = 0;  // heap of the simulation after its first step, per element
  std::vector<double> tip_path;  // the tip's mean z-displacement after each step
};

// The largest deviation of a run's tip path from the reference's, relative to the largest
// displacement of the reference's: the motion's error, not only the end point's.
double path_deviation(const RunResult& r, const RunResult& ref) {
  if (ref.tip_path.size() != r.tip_path.size() || ref.tip_path.empty()) return std::nan("");
  double largest = 0, deviation = 0;
  for (size_t s = 0; s < r.tip_path.size(); ++s) {
    largest = std::max(largest, std::abs(ref.tip_path[s]));
    deviation = std::max(deviation, std::abs(r.tip_path[s] - ref.tip_path[s]));
  }
  return deviation / largest;
}

// Bytes the heap holds now (glibc; 0 elsewhere): the memory a simulation owns is the change.
long heap_bytes() {
#ifdef __GLIBC__
  const struct mallinfo2 info = mallinfo2();
  return static_cast<long>(info.uordblks + info.hblkhd);
#else
  return 0;
#endif
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

Config config_by_name(const std::string& name, const Options& opt) {
  Config c{name, "pcg", {}, opt.reuse_angle};
  if (name == "paper" || name == "paper_warm" || name == "reference") c.reuse_angle = 0;
  if (name == "paper") {  // the paper's setting: Jacobi PCG capped at 20, cold start
    c.pcg = {20, 1e-6, false, PreconditionerKind::Jacobi};
  } else if (name == "paper_warm") {
    c.pcg = {20, 1e-6, true, PreconditionerKind::Jacobi};
  } else if (name == "block_jacobi") {  // warm-started block-Jacobi run to the tolerance
    c.pcg = {1000, 1e-6, true, PreconditionerKind::BlockJacobi};
  } else if (name == "default") {  // corotate's default (corotate.PCG()): see bench/README.md
    c.pcg = PCGSettings{};
  } else if (name == "reference_factor") {  // the default's tolerance with a reused fine factor
    c.pcg = {20, 1e-2, true, PreconditionerKind::ReferenceFactor};
  } else if (name == "reference") {  // converged: tight tolerance, no cap that binds
    c.pcg = {10000, 1e-10, true, PreconditionerKind::TwoLevel};
  } else if (name == "custom") {
    c.pcg = opt.custom;
  } else if (name == "direct") {
    c.solver = "direct";
    // named by the backend when one is asked for (--direct), so that runs compare in one table
    if (opt.direct != SparseCholesky::Backend::Auto)
      c.name += std::string("_") + DirectSolver(opt.direct).backend_name();
  } else {
    throw InvalidInput("unknown configuration '" + name + "'");
  }
  return c;
}

RunResult run(const bench::TetMesh& mesh, const Config& config, const Options& opt) {
  RunResult r;
  const auto t0 = clock_type::now();
  std::unique_ptr<LinearSolver> solver;
  if (config.solver == "direct") solver = std::make_unique<DirectSolver>(opt.direct);
  else solver = std::make_unique<PCG>(config.pcg);
  Material material{1e7, 0.3, 1000.0};
  IntegratorSettings settings;  // linearised implicit Euler
  settings.time_step = opt.dt;
  settings.lumped_mass = opt.lumped;
  settings.matrix_reuse_angle = config.reuse_angle;
  const long heap_before = heap_bytes();
  Simulation sim(make_model("corotational", mesh.cell_type, mesh.points, mesh.cells, material), settings,
                 std::move(solver));
  if (!opt.checks) sim.set_failure_policy(FailurePolicy::Ignore);
  const double x_min = mesh.points.row(0).minCoeff(), x_max = mesh.points.row(0).maxCoeff();
  std::vector<Index> fixed, tip;
  for (Index i = 0; i < mesh.points.cols(); ++i) {
    if (mesh.points(0, i) <= x_min + 1e-9) fixed.push_back(i);
    if (mesh.points(0, i) >= x_max - 1e-9) tip.push_back(i);
  }
  sim.set_fixed_nodes(fixed);
  sim.set_gravity(Vec3(0, 0, -9.81));
  r.precompute_ms = std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();

  std::vector<double> total, asm_, sol;
  double iterations = 0;
  auto tip_z = [&] {
    double z = 0;
    for (Index i : tip) z += sim.positions()(2, i) - mesh.points(2, i);
    return z / tip.size();
  };
  if (opt.trace)
    std::printf(
        "# %s: state  tip_z[m]  energy[J] (elastic + kinetic - load work)  then of the step from it: iters  "
        "rel_residual  stalled  energy_growth\n",
        config.name.c_str());
  for (int s = 0; s < opt.steps; ++s) {
    // The trace's energy is that of the state the step starts from: kinetic energy (consistent
    // mass) and load work now, elastic energy from the step's own sweep.
    double start_kinetic_minus_work = 0;
    if (opt.trace)
      start_kinetic_minus_work =
          sim.kinetic_energy() - as_dofs(sim.gravity_forces()).dot(as_dofs(sim.positions()) - as_dofs(mesh.points));
    const double start_tip = tip_z();
    const double wall_before = sim.stats().wall_ms;
    sim.step(1);
    const double wall_ms = sim.stats().wall_ms - wall_before;  // the whole call, as a user times it
    const auto& st = sim.stats().last;
    if (opt.trace)
      std::printf("# %4d %10.5f %12.5g %4d %10.3g %d %d\n", s, start_tip, st.start_energy + start_kinetic_minus_work,
                  st.solve.iterations, st.solve.relative_residual, int(st.solver_stalled), int(st.energy_growth));
    if (s == 0) {
      r.first_step_ms = wall_ms;  // includes a preconditioner factorization
      r.bytes_per_element = double(heap_bytes() - heap_before) / mesh.cells.rows();
    }
    total.push_back(wall_ms);
    asm_.push_back(st.assembly_ms);
    sol.push_back(st.solve_ms);
    iterations += st.solve.iterations;
    r.tip_path.push_back(tip_z());
    r.max_iterations = std::max(r.max_iterations, st.solve.iterations);
  }
  r.median_ms = median(total);
  r.assembly_ms = median(asm_);
  r.solve_ms = median(sol);
  r.iterations = iterations / opt.steps;
  r.real_time_ratio = sim.stats().real_time_ratio();
  r.tip_z = tip_z();
  r.stalled_steps = sim.stats().stalled_steps;
  r.energy_growth_steps = sim.stats().energy_growth_steps;
  return r;
}

void usage() {
  std::puts(
      "usage: corotate_bench [options]\n"
      "Times the co-rotational implicit step on the standard beam (bench/README.md) or a mesh.\n"
      "  --sizes 1,2,4,8     refinement factors of the 10x2x2-cube beam (1 -> 240 tets, 2 -> 1920,\n"
      "                      4 -> 15360, 8 -> 122880); default 1,2,4,8\n"
      "  --mesh FILE         a mesh instead of the beam (fixed: nodes at min x): through `corotate bench`,\n"
      "                      any file corotate.read_mesh reads; run directly, a --write-mesh text file\n"
      "  --configs LIST      solver configurations among paper, paper_warm, block_jacobi, default,\n"
      "                      reference_factor, direct, reference, custom; default paper,default\n"
      "  --steps N           steps per run (default 100)\n"
      "  --dt SECONDS        time step (default 0.01)\n"
      "  --lumped            lumped instead of consistent mass\n"
      "  --element E         the beam's element: tet4 (default: 6 tets per cube), tet10, hex8 or hex20\n"
      "                      (corotate.beam's mesh, node for node)\n"
      "  --write-mesh FILE   write the (first) beam's mesh as text (n m k, points, cells, cell type) and stop\n"
      "  --no-checks         skip the loud-failure checks (failure policy ignore; default: warn)\n"
      "  --threads N         threads of the element sweep, SpMV and smoother (default 1; OpenMP)\n"
      "  --direct B          the 'direct' configuration's Cholesky: eigen, cholmod or supernodal (default:\n"
      "                      cholmod when built with SuiteSparse, else supernodal; the two-level coarse\n"
      "                      solve always uses supernodal)\n"
      "  --no-reference      skip the converged reference run (timings only; dev[%] prints nan)\n"
      "  --trace             print one line per step of every run: tip, total energy, iterations,\n"
      "                      relative residual, and the loud-failure flags (energy: elastic energy at\n"
      "                      the step's start with the kinetic energy and load work at its end)\n"
      "  --preconditioner P, --tolerance T, --cap N, --cold\n"
      "                      settings of the 'custom' configuration (none, jacobi, block_jacobi,\n"
      "                      reference_factor, two_level; default block_jacobi, 1e-6, 20, warm start)\n"
      "  --reuse-angle A     matrix_reuse_angle [rad] of every configuration but paper, paper_warm and\n"
      "                      the reference, which assemble at every step (default: the library's)\n"
      "  --scenario mass_spring [--frames N] [--integrator I]\n"
      "                      (first option) explicit mass-spring cloth and lattices instead; see\n"
      "                      bench/mass_spring_scenario.hpp\n"
      "  --scenario feedback [--queries N] [--tool K]\n"
      "                      (first option) one haptic feedback query per method on a 10,290-tet\n"
      "                      beam; see bench/feedback_scenario.hpp\n"
      "  --scenario embedding [--vertices N] [--coupling-vertices N] [--coupling-cells N]\n"
      "                      (first option) the embedded render surface: per-frame update of\n"
      "                      12,500 vertices, coupling 1M vertices to 100k tets; see\n"
      "                      bench/embedding_scenario.hpp\n"
      "  --scenario grab [--sizes 2,4] [--mesh FILE] [--stiffness K]\n"
      "                      (first option) frame times after grabbing and releasing a node (attach\n"
      "                      vs fix); see bench/grab_scenario.hpp\n"
      "  --scenario rotations [--elements N] [--turn RAD]\n"
      "                      (first option) the element sweep's polar rotations alone, one\n"
      "                      call per element vs batched; see bench/rotation_scenario.hpp\n"
      "  --scenario products [--sizes 4,8] [--threads N]\n"
      "                      (first option) the element sweep, the mass copy and the matrix-vector\n"
      "                      products (double, symmetric, float32) alone; see bench/products_scenario.hpp\n"
      "Each mesh first runs 'reference' (two-level PCG to 1e-10) so deviations are measured honestly.");
}

}  // namespace

namespace {
// Threads that wait at a barrier sleep instead of spinning on a core another process needs
// (the Python package sets the same at import; errors-and-threads guide). libgomp reads the
// variable once, as it loads, before main: so the benchmark sets it and starts itself again,
// unless it was set (a run that measures the spinning policy sets OMP_WAIT_POLICY=active).
void sleep_at_barriers(char** argv) {
#if defined(__linux__)
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  if (setenv("OMP_WAIT_POLICY", "PASSIVE", 0) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: then run as we are
#else
  (void)argv;
#endif
}
}  // namespace

int main(int argc, char** argv) {
  sleep_at_barriers(argv);
  Options opt;
  try {
    // --scenario mass_spring: the explicit mass-spring benchmark (mass_spring_scenario.hpp).
    if (argc >= 3 && std::string(argv[1]) == "--scenario") {
      if (std::string(argv[2]) == "mass_spring") return bench::mass_spring_main(argc - 3, argv + 3);
      if (std::string(argv[2]) == "feedback") return bench::feedback_main(argc - 3, argv + 3);
      if (std::string(argv[2]) == "embedding") return bench::embedding_main(argc - 3, argv + 3);
      if (std::string(argv[2]) == "grab") return bench::grab_main(argc - 3, argv + 3);
      if (std::string(argv[2]) == "rotations") return bench::rotations_main(argc - 3, argv + 3);
      if (std::string(argv[2]) == "products") return bench::products_main(argc - 3, argv + 3);
      if (std::string(argv[2]) != "beam")
        throw InvalidInput(std::string("unknown scenario ") + argv[2] +
                           " (beam, mass_spring, feedback, embedding, grab, rotations, products)");
      argc -= 2, argv += 2;
    }
    for (int a = 1; a < argc; ++a) {
      const std::string arg = argv[a];
      auto value = [&]() -> std::string {
        if (a + 1 >= argc) throw InvalidInput("missing value after " + arg);
        return argv[++a];
      };
      if (arg == "--help" || arg == "-h") {
        usage();
        return 0;
      } else if (arg == "--sizes") {
        opt.sizes.clear();
        opt.sizes = bench::parse_sizes(value());
      } else if (arg == "--mesh") opt.mesh_path = value();
      else if (arg == "--configs") opt.configs = bench::split_list(value());
      else if (arg == "--steps") opt.steps = std::stoi(value());
      else if (arg == "--dt") opt.dt = std::stod(value());
      else if (arg == "--lumped") opt.lumped = true;
      else if (arg == "--element") opt.element = value();
      else if (arg == "--write-mesh") opt.write_mesh = value();
      else if (arg == "--no-checks") opt.checks = false;
      else if (arg == "--trace") opt.trace = true;
      else if (arg == "--no-reference") opt.reference = false;
      else if (arg == "--direct") {
        const std::string name = value();
        if (name == "eigen") opt.direct = SparseCholesky::Backend::Eigen;
        else if (name == "cholmod") opt.direct = SparseCholesky::Backend::Cholmod;
        else if (name == "supernodal") opt.direct = SparseCholesky::Backend::Supernodal;
        else throw InvalidInput("--direct takes eigen, cholmod or supernodal");
      } else if (arg == "--threads") set_num_threads(std::stoi(value()));
      else if (arg == "--preconditioner") opt.custom.preconditioner = preconditioner_kind_from_name(value());
      else if (arg == "--tolerance") opt.custom.tolerance = std::stod(value());
      else if (arg == "--cap") opt.custom.max_iterations = std::stoi(value());
      else if (arg == "--cold") opt.custom.warm_start = false;
      else if (arg == "--reuse-angle") opt.reuse_angle = std::stod(value());
      else throw InvalidInput("unknown option " + arg + " (see --help)");
    }
    std::vector<std::pair<std::string, bench::TetMesh>> meshes;
    if (!opt.mesh_path.empty())  // label: the file name without folders
      meshes.emplace_back(opt.mesh_path.substr(opt.mesh_path.find_last_of("/\\") + 1), bench::read_mesh(opt.mesh_path));
    else
      for (int s : opt.sizes)
        meshes.emplace_back(
            "beam " + std::to_string(10 * s) + "x" + std::to_string(2 * s) + "x" + std::to_string(2 * s),
            bench::structured_beam(opt.element, 10 * s, 2 * s, 2 * s, 5.0, 1.0, 1.0));
    if (!opt.write_mesh.empty()) {
      bench::write_mesh(opt.write_mesh, meshes.front().second);
      return 0;
    }

    std::printf(
        "scenario: corotational %s, E=1e7 nu=0.3 rho=1000, gravity -z, dt=%g, %d steps, %s mass, %s, %d thread(s)\n",
        opt.element.c_str(), opt.dt, opt.steps, opt.lumped ? "lumped" : "consistent",
        opt.checks ? "loud-failure checks" : "no checks", num_threads());
    std::printf("matrix_reuse_angle: %g rad (paper, paper_warm and the reference: 0, every step assembled)\n",
                opt.reuse_angle);
    const char* policy = std::getenv("OMP_WAIT_POLICY");
    std::printf("OpenMP threads waiting at barriers: OMP_WAIT_POLICY=%s\n", policy ? policy : "(unset)");
    std::printf("instruction set of the hot loops: %s\n", build_info().instruction_set.c_str());
    std::printf("direct solver (config 'direct'): %s (auto: %s from %ld DOFs); two-level coarse solver: %s\n",
                DirectSolver(opt.direct).backend_name(), SparseCholesky::have_cholmod() ? "CHOLMOD" : "supernodal",
                long(SparseCholesky::kSupernodalFromDofs), "supernodal");
    std::printf("%-16s %7s %-16s %9s %9s %8s %7s %7s %7s %6s %8s %10s %8s %8s %s\n", "mesh", "elems", "config",
                "precmp_ms", "1st_step", "ms/step", "asm", "solve", "iters", "maxit", "rt_ratio", "tip_z[m]", "dev[%]",
                "path[%]", "stalled/growth  B/elem");
    for (const auto& [label, mesh] : meshes) {
      RunResult ref;
      ref.tip_z = std::nan("");
      if (opt.reference) ref = run(mesh, config_by_name("reference", opt), opt);
      auto print = [&](const std::string& name, const RunResult& r) {
        std::printf(
            "%-16s %7ld %-16s %9.1f %9.1f %8.3f %7.3f %7.3f %7.2f %6d %8.2f %10.5f %8.3f %8.3f %lld/%lld %7.0f\n",
            label.c_str(), static_cast<long>(mesh.cells.rows()), name.c_str(), r.precompute_ms, r.first_step_ms,
            r.median_ms, r.assembly_ms, r.solve_ms, r.iterations, r.max_iterations, r.real_time_ratio, r.tip_z,
            100.0 * (r.tip_z - ref.tip_z) / ref.tip_z, 100.0 * path_deviation(r, ref), r.stalled_steps,
            r.energy_growth_steps, r.bytes_per_element);
        std::fflush(stdout);
      };
      if (opt.reference) print("reference", ref);
      for (const auto& name : opt.configs) {
        const Config config = config_by_name(name, opt);
        print(config.name, run(mesh, config, opt));
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "corotate_bench: %s\n", e.what());
    return 2;
  }
  return 0;
}
