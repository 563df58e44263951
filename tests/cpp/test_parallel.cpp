// Threads change the speed, never the answer: the element sweep runs its chunks in a fixed
// order whose concurrent parts share no node (sweep_schedule.hpp) and sums energies per chunk
// in chunk order, SpMV and the smoother split rows; so a run on two threads repeats a
// one-thread run bit for bit.
#include <algorithm>
#include <set>

#include "corotate/fem/assembled_model.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/parallel.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/pcg.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

const Material kMaterial{1e6, 0.3, 1000.0};

// Sets the thread count for a scope and restores it (other tests run on one thread).
struct Threads {
  int before = num_threads();
  explicit Threads(int n) { set_num_threads(n); }
  ~Threads() { set_num_threads(before); }
};

// 48 x 4 x 4 cubes: 4,608 tets in 9 chunks, split into two halves that run concurrently and
// their separator; 1,225 nodes (above the SpMV threshold).
Nodes run_beam(int threads, const std::string& preconditioner, double* energy) {
  const Threads scope(threads);
  const auto mesh = fixtures::tet_beam(48, 4, 4);
  IntegratorSettings settings;
  settings.time_step = 1e-2;
  PCGSettings pcg;
  pcg.preconditioner = preconditioner_kind_from_name(preconditioner);
  Simulation sim(make_model("corotational", "tetra", mesh.points, mesh.cells, kMaterial), settings,
                 std::make_unique<PCG>(pcg));
  sim.set_fixed_nodes(fixtures::nodes_at_x0(mesh));
  sim.set_gravity(Vec3(0, 0, -9.81));
  sim.step(20);
  *energy = sim.stats().last.start_energy;
  return sim.positions();
}

}  // namespace

TEST(thread_count_is_validated) {
  const int before = num_threads();
  CHECK_THROWS(set_num_threads(0), InvalidInput);
  CHECK_THROWS(set_num_threads(-3), InvalidInput);
  if (!have_openmp()) CHECK_THROWS(set_num_threads(2), InvalidInput);
  CHECK(num_threads() == before);
  CHECK(available_threads() >= 1);
}

TEST(two_threads_repeat_one_thread_to_the_bit) {
  if (!have_openmp()) {
    std::puts("  skipped: built without OpenMP");
    return;
  }
  for (const std::string preconditioner : {"two_level", "block_jacobi"}) {
    double e1 = 0, e2 = 0, e3 = 0;
    const Nodes one = run_beam(1, preconditioner, &e1);
    const Nodes two = run_beam(2, preconditioner, &e2);
    const Nodes three = run_beam(3, preconditioner, &e3);  // more threads than parts: fine too
    CHECK(one.minCoeff() < -1e-3 || one.row(2).minCoeff() < -1e-3);  // it moved
    CHECK((one - two).cwiseAbs().maxCoeff() == 0.0);
    CHECK((one - three).cwiseAbs().maxCoeff() == 0.0);
    CHECK(e1 == e2 && e1 == e3 && e1 > 0);
  }
}

TEST(threaded_tangent_and_forces_match_a_serial_sweep) {
  // The element-matrix path (exact tangent, hyperelastic law) under two threads against one.
  const auto mesh = fixtures::tet_beam(48, 4, 4);
  auto model = make_model("neohookean", "tetra", mesh.points, mesh.cells, kMaterial);
  Nodes x = mesh.points;
  for (Index i = 0; i < x.cols(); ++i) x.col(i) += 0.05 * Vec3(std::sin(x(0, i)), std::cos(x(1, i)), x(2, i) * 0.3);
  auto evaluate = [&](int threads, Nodes& f, BlockSparseMatrix& K, double& energy) {
    const Threads scope(threads);
    Request what;
    what.forces = true;
    what.energy = true;
    what.stiffness = StiffnessKind::Tangent;
    f.setZero(3, x.cols());
    K = model->pattern();
    K.set_zero();
    Results out;
    out.forces = &f;
    out.stiffness = &K;
    model->evaluate(x, what, out);
    energy = out.energy;
  };
  Nodes f1, f2;
  BlockSparseMatrix K1, K2;
  double e1 = 0, e2 = 0;
  evaluate(1, f1, K1, e1);
  evaluate(have_openmp() ? 2 : 1, f2, K2, e2);
  CHECK(f1.norm() > 0 && e1 > 0);
  CHECK(f1 == f2);
  CHECK(K1.values() == K2.values());
  CHECK(e1 == e2);
}

TEST(an_error_inside_the_threaded_sweep_is_thrown_not_fatal) {
  // The geometric stiffness of an inverted element throws from inside the parallel loop.
  const auto mesh = fixtures::tet_beam(48, 4, 4);
  auto model = make_model("neohookean", "tetra", mesh.points, mesh.cells, kMaterial);
  Nodes x = mesh.points;
  x.row(2) *= -1.0;  // every element inverted
  const Threads scope(have_openmp() ? 2 : 1);
  Request what;
  what.stiffness = StiffnessKind::Geometric;
  BlockSparseMatrix K = model->pattern();
  Results out;
  out.stiffness = &K;
  CHECK_THROWS(model->evaluate(x, what, out), InvalidInput);
}
