// corotate_bench --scenario products: the pieces of an implicit step that a whole-step
// benchmark cannot time alone, on the standard beam's system A = M + dt^2 K (consistent mass,
// dt = 0.01, the rest state bent a little): the element sweep (rotations, forces, stiffness
// and scatter, after the copy of the mass) into the double matrix and straight into the
// float32 system (what the default solver's steps do after the first), the copy of the mass
// into the system matrix, the matrix-vector products (full, symmetric in double, and from
// the float32 copy the two-level V-cycle and CG use) and the conversion to that copy (what
// a step with a double system pays). Median of interleaved repetitions, each the mean of a
// batch of calls.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "beam_scenario.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/parallel.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate::bench {

inline int products_main(int argc, char** argv) {
  std::vector<int> sizes{4, 8};
  int repeats = 21;
  for (int a = 0; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--sizes" && a + 1 < argc) sizes = parse_sizes(argv[++a]);
    else if (arg == "--repeats" && a + 1 < argc) repeats = std::stoi(argv[++a]);
    else if (arg == "--threads" && a + 1 < argc) set_num_threads(std::stoi(argv[++a]));
    else if (arg == "--help" || arg == "-h") {
      std::puts(
          "usage: corotate_bench --scenario products [--sizes 4,8 (beam refinements)] [--repeats N (21)]\n"
          "       [--threads N (1)]");
      return 0;
    } else throw InvalidInput("unknown option " + arg + " for --scenario products");
  }
  if (repeats < 1) throw InvalidInput("--repeats must be at least 1");
  std::printf("products: median of %d interleaved repetitions, %d thread(s); ms per call\n", repeats, num_threads());
  std::printf("%8s %9s %9s %10s %10s %11s %11s %11s %10s\n", "elems", "sweep", "sweep_f32", "mass_copy", "product",
              "symmetric", "float32", "float_copy", "float_err");
  for (int s : sizes) {
    if (s < 1) throw InvalidInput("--sizes must be positive");
    const TetMesh mesh = structured_beam("tet4", 10 * s, 2 * s, 2 * s, 5.0, 1.0, 1.0);
    auto model = make_model("corotational", mesh.cell_type, mesh.points, mesh.cells, Material{1e7, 0.3, 1000.0});
    Nodes x = mesh.points;
    for (Index i = 0; i < x.cols(); ++i) x(2, i) -= 0.01 * x(0, i) * x(0, i);  // bent: rotations to extract
    const Nodes y = x;
    const BlockSparseMatrix mass = model->mass_matrix(false);
    BlockSparseMatrix A = model->pattern();
    Nodes f = Nodes::Zero(3, x.cols());
    Request what;
    what.forces = true;
    what.forces_at = &y;
    what.stiffness = StiffnessKind::Model;
    what.stiffness_scale = 1e-4;  // dt^2
    what.lower_blocks = false;    // as the default solver's step
    Results out;
    out.forces = &f;
    out.stiffness = &A;
    auto sweep = [&] {
      f.setZero();
      A.assign_scaled(1.0, mass, false);
      model->evaluate(x, what, out);
    };
    // The whole matrix once (its lower blocks too), for the full product and the reference.
    A.assign_scaled(1.0, mass);
    what.lower_blocks = true;
    model->evaluate(x, what, out);
    what.lower_blocks = false;
    const Vec v = Vec::Random(A.num_dofs());
    Vec y_full(A.num_dofs()), y_sym(A.num_dofs()), y_float(A.num_dofs());
    SinglePrecisionSymmetric single;
    single.assign(A);
    Results out_single;
    out_single.forces = &f;
    out_single.single_stiffness = &single;
    auto sweep_single = [&] {
      f.setZero();
      single.start_assembly(mass, 1.0, 1);
      model->evaluate(x, what, out_single);
    };
    const std::vector<std::function<void()>> pieces = {
        sweep,
        sweep_single,
        [&] { A.assign_scaled(1.0, mass, false); },
        [&] { A.multiply(v, y_full); },
        [&] { A.multiply_symmetric(v, y_sym); },
        [&] { single.multiply(v, y_float); },
        [&] { single.assign(A); },
    };
    const int batch = std::max(1, 2000000 / static_cast<int>(mesh.cells.rows()));  // ~a few ms per batch
    std::vector<std::vector<double>> ms(pieces.size());
    for (int r = 0; r < repeats; ++r)
      for (size_t p = 0; p < pieces.size(); ++p) {
        const int calls = p <= 1 ? std::max(1, batch / 8) : batch;
        const auto t0 = std::chrono::steady_clock::now();
        for (int c = 0; c < calls; ++c) pieces[p]();
        ms[p].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
                        calls);
      }
    // The float32 copy against the double product, on the system the sweep leaves (the mass
    // copy alone, last timed, left the stiffness out).
    sweep();
    A.multiply_symmetric(v, y_sym);
    single.assign(A);
    single.multiply(v, y_float);
    auto median = [](std::vector<double> t) {
      std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
      return t[t.size() / 2];
    };
    std::printf("%8ld %9.3f %9.3f %10.3f %10.4f %11.4f %11.4f %11.4f %10.1e\n", static_cast<long>(mesh.cells.rows()),
                median(ms[0]), median(ms[1]), median(ms[2]), median(ms[3]), median(ms[4]), median(ms[5]), median(ms[6]),
                (y_float - y_sym).norm() / y_sym.norm());
  }
  return 0;
}

}  // namespace corotate::bench
