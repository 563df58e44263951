// The simulation and its integrator seam: one definition of fixed nodes for every
// integrator, and a transactional step that restores everything, warm starts included.
#include <limits>
#include <string>

#include "corotate/integrators/kept_system.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

const Material kMaterial{1e6, 0.3, 1000.0};

// A PCG that throws on a chosen call: a failure in the middle of a multi-step call.
class FlakySolver final : public LinearSolver {
 public:
  int calls = 0, fail_at = -1;
  void reset() override { inner_.reset(); }
  void set_geometry(const Nodes& rest) override { inner_.set_geometry(rest); }
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override {
    if (++calls == fail_at) throw SolverFailure("injected failure");
    return inner_.solve(A, b, x);
  }

 private:
  PCG inner_;
};

// The direct solver told nothing: it factorizes at every solve.
class FactorizingEverySolve final : public LinearSolver {
 public:
  void reset() override { inner_.reset(); }
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override { return inner_.solve(A, b, x); }

 private:
  DirectSolver inner_;
};

// A solver that asks for the lower blocks (as a preconditioner about to factorize does) at
// every `every`-th solve only, and records whether the matrix it then got has them: the lower
// blocks mirror the upper ones when the full product equals the symmetric one (upper blocks).
class AskingForLowerBlocks final : public LinearSolver {
 public:
  explicit AskingForLowerBlocks(int every) : every_(every) {}
  int asked = 0, asked_on_kept = 0, lacking = 0;
  void reset() override { inner_.reset(); }
  void constraints_changed(const FixedDofs& fixed) override { inner_.constraints_changed(fixed); }
  void same_matrix_next() override { kept_ = true; }
  bool needs_lower_blocks() const override { return solves_ % every_ == every_ - 1; }
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override {
    if (needs_lower_blocks()) {
      ++asked;
      asked_on_kept += kept_;
      const Vec v = fixtures::random_matrix<Vec>(A.num_dofs(), 1);
      Vec full(A.num_dofs()), upper(A.num_dofs());
      A.multiply(v, full);
      A.multiply_symmetric(v, upper);
      lacking += (full - upper).norm() > 1e-12 * upper.norm();
    }
    ++solves_;
    kept_ = false;
    return inner_.solve(A, b, x);
  }

 private:
  const int every_;
  int solves_ = 0;
  bool kept_ = false;
  PCG inner_{PCGSettings{2000, 1e-10, true, PreconditionerKind::BlockJacobi}};  // reads no lower block
};

std::unique_ptr<Simulation> beam(IntegratorKind kind, std::unique_ptr<LinearSolver> solver = nullptr,
                                 double matrix_reuse_angle = IntegratorSettings{}.matrix_reuse_angle) {
  const auto mesh = fixtures::tet_beam(4, 1, 1);
  IntegratorSettings settings;
  settings.kind = kind;
  settings.matrix_reuse_angle = matrix_reuse_angle;
  settings.time_step = is_explicit(kind) ? 1e-3 : 1e-2;
  auto sim = std::make_unique<Simulation>(make_model("corotational", "tetra", mesh.points, mesh.cells, kMaterial),
                                          settings, std::move(solver));
  sim->set_fixed_nodes(fixtures::nodes_at_x0(mesh));
  sim->set_gravity(Vec3(0, 0, -9.81));
  return sim;
}

}  // namespace

TEST(fixed_nodes_keep_their_velocity_under_every_integrator) {
  for (const auto& name : integrator_names()) {
    auto sim = beam(integrator_from_name(name));
    const Index node = sim->fixed_nodes().front();
    const Vec3 start = sim->positions().col(node), velocity(0.1, -0.2, 0.3);
    sim->velocities().col(node) = velocity;  // prescribed motion
    sim->step(5);
    CHECK((sim->velocities().col(node) - velocity).norm() == 0.0);
    CHECK((sim->positions().col(node) - (start + sim->time() * velocity)).norm() <= 1e-14);
    // and the free nodes fell
    CHECK(sim->positions().row(2).minCoeff() < -1e-6);
  }
}

TEST(a_failed_step_restores_everything_including_the_warm_start) {
  auto a_solver = std::make_unique<FlakySolver>();
  FlakySolver* flaky = a_solver.get();
  // (Every step assembles its matrix: a kept one is not part of the restored state, below.)
  auto a = beam(IntegratorKind::Linearized, std::move(a_solver), 0.0);
  auto b = beam(IntegratorKind::Linearized, std::make_unique<FlakySolver>(), 0.0);
  a->step(3);
  b->step(3);
  const Nodes x = a->positions(), v = a->velocities();
  const double t = a->time();
  const long long steps = a->stats().steps;
  flaky->fail_at = flaky->calls + 2;  // the second step of the next call fails
  CHECK_THROWS(a->step(2), SolverFailure);
  CHECK(a->positions() == x && a->velocities() == v && a->time() == t && a->stats().steps == steps);
  // The next step equals that of a twin that never failed, bit for bit: the solver's warm
  // start and the rotation extraction's warm starts were restored with the state.
  a->step(1);
  b->step(1);
  CHECK(a->positions() == b->positions());
  CHECK(a->velocities() == b->velocities());
  // The same when the call's only step fails (no copy of the state is taken then).
  const Nodes x1 = a->positions(), v1 = a->velocities(), a1 = a->accelerations();
  flaky->fail_at = flaky->calls + 1;
  CHECK_THROWS(a->step(1), SolverFailure);
  CHECK(a->positions() == x1 && a->velocities() == v1 && a->accelerations() == a1);
  a->step(1);
  b->step(1);
  CHECK(a->positions() == b->positions());
  CHECK(a->velocities() == b->velocities());
}

TEST(the_kept_matrix_is_rebuilt_before_its_drift_reaches_the_angle) {
  // The control alone (kept_system.hpp): a body turning 0.012 rad per step beyond its parts'
  // rotation, angle 0.05.
  KeptSystem kept;
  KeptSystem::Key key;
  CHECK(!kept.may_keep(key, 0.05));  // nothing assembled
  kept.assembled(key, std::numeric_limits<double>::infinity());
  CHECK(!kept.may_keep(key, 0.05));  // the first assembly knows no rate: the next assembles too
  kept.assembled(key, 0.012);        // the turn since, in one step
  std::string pattern;
  double drift = 0;
  for (int step = 0; step < 12; ++step) {
    if (kept.may_keep(key, 0.05)) {
      drift += 0.012;
      kept.measured(drift);
      pattern += 'K';
    } else {
      kept.assembled(key, drift + 0.012);
      drift = 0;
      pattern += 'A';
    }
  }
  // Kept at 0.012, 0.024, 0.036, 0.048: the fifth would start at 0.06.
  CHECK(pattern == "KKKKAKKKKAKK");
  // Another key (solver, target, mass, springs, model), angle 0, or forget(): assemble.
  KeptSystem::Key other = key;
  other.attachments_stiffness = 1;
  CHECK(kept.may_keep(key, 0.05) && !kept.may_keep(other, 0.05) && !kept.may_keep(key, 0.0));
  kept.forget();
  CHECK(!kept.may_keep(key, 0.05));
  // A drift that stops growing keeps the matrix; one that jumps is predicted from its jump.
  kept.assembled(key, 0.0);
  kept.measured(0.03);
  CHECK(!kept.may_keep(key, 0.05));  // 0.03 + 0.03
  kept.assembled(key, 0.0);
  kept.measured(0.01);
  kept.measured(0.01);
  CHECK(kept.may_keep(key, 0.05));
}

TEST(a_failed_step_forgets_the_kept_matrix) {
  // A failed step may have assembled part of a new matrix: the next one assembles afresh
  // where its twin keeps its matrix, and the two differ only by the kept matrix's lag.
  auto a_solver = std::make_unique<FlakySolver>();
  FlakySolver* flaky = a_solver.get();
  auto a = beam(IntegratorKind::Linearized, std::move(a_solver));
  auto b = beam(IntegratorKind::Linearized, std::make_unique<FlakySolver>());
  a->step(3);
  b->step(3);
  CHECK(a->stats().kept_matrix_steps == 1 && b->stats().kept_matrix_steps == 1);  // (the first two assemble)
  flaky->fail_at = flaky->calls + 1;
  CHECK_THROWS(a->step(1), SolverFailure);
  a->step(1);
  b->step(1);
  CHECK(!a->stats().last.kept_matrix && b->stats().last.kept_matrix);
  const Nodes& rest = a->model().rest_positions();
  const double moved = (b->positions() - rest).norm(), apart = (a->positions() - b->positions()).norm();
  CHECK(apart > 0 && apart <= 1e-3 * moved);
}

TEST(a_direct_solve_of_a_kept_matrix_reuses_its_factor_to_the_bit) {
  // A step that keeps its matrix solves with the direct solver's last factor of it: the same
  // factor a factorization would give, so the same motion to the bit.
  auto direct = std::make_unique<DirectSolver>();
  const DirectSolver* reusing = direct.get();
  auto a = beam(IntegratorKind::Linearized, std::move(direct));
  auto b = beam(IntegratorKind::Linearized, std::make_unique<FactorizingEverySolve>());
  a->step(30);
  b->step(30);
  CHECK(a->stats().kept_matrix_steps > 10);
  CHECK(reusing->factor_reuses() == a->stats().kept_matrix_steps);
  CHECK((a->positions() - b->positions()).norm() == 0.0);
  CHECK((a->velocities() - b->velocities()).norm() == 0.0);
}

TEST(a_step_whose_solver_asks_for_the_lower_blocks_gets_them_even_where_it_could_keep_its_matrix) {
  // A reference factor asks for them when it pays to factorize afresh (a body that sagged far
  // from the state of its factor), on any step. A kept matrix assembled without them was
  // passed on as it was: Table 1's cage with a converged PCG (double products) then
  // factorized stale lower blocks and failed as "not positive definite". The kept matrix
  // now gets them mirrored from its upper ones (BlockSparseMatrix::mirror_upper_blocks).
  auto asking = std::make_unique<AskingForLowerBlocks>(5);
  const AskingForLowerBlocks* solver = asking.get();
  auto sim = beam(IntegratorKind::Linearized, std::move(asking));
  sim->step(40);
  std::printf("  asked %d times, %d of them on steps that kept their matrix; %lld kept steps of 40\n", solver->asked,
              solver->asked_on_kept, sim->stats().kept_matrix_steps);
  CHECK(solver->asked == 8 && sim->stats().kept_matrix_steps > 10);
  CHECK(solver->asked_on_kept > 0 && solver->lacking == 0);  // (7 of the 8 lacked them before)
}

TEST(a_direct_solver_reuses_a_factor_only_for_the_matrix_it_factorized) {
  const auto mesh = fixtures::tet_beam(4, 2, 2);
  const auto s = fixtures::implicit_system(mesh, kMaterial, 0.01);
  BlockSparseMatrix other = s.A;
  other.assign_scaled(2.0, s.A, true);  // another matrix, twice the values
  const Vec b = fixtures::random_matrix<Vec>(s.A.num_dofs(), 1);
  DirectSolver solver;
  Vec x, y, fresh;
  solver.solve(s.A, b, x);
  solver.same_matrix_next();
  solver.solve(s.A, b, y);
  CHECK(solver.factor_reuses() == 1 && (x - y).norm() == 0.0);
  solver.same_matrix_next();  // a hint for another matrix: factorized
  solver.solve(other, b, y);
  CHECK(solver.factor_reuses() == 1 && (2 * y - x).norm() <= 1e-10 * x.norm());
  solver.reset();  // forgets the factor too
  solver.same_matrix_next();
  solver.solve(other, b, fresh);
  CHECK(solver.factor_reuses() == 1 && (fresh - y).norm() == 0.0);
  solver.same_matrix_next();
  solver.solve(other, b, y);
  solver.solve(other, b, y);  // the hint holds for one solve only
  CHECK(solver.factor_reuses() == 2);
}

TEST(settings_are_validated_before_anything_changes) {
  auto sim = beam(IntegratorKind::Linearized);
  IntegratorSettings bad = sim->settings();
  bad.time_step = -1;
  CHECK_THROWS(sim->set_settings(bad), InvalidInput);
  CHECK(sim->settings().time_step == 1e-2);
  bad = sim->settings();
  bad.kind = IntegratorKind::Newton;
  bad.stiffness_damping = 0.1;  // not a potential
  CHECK_THROWS(sim->set_settings(bad), InvalidInput);
  CHECK(sim->settings().kind == IntegratorKind::Linearized);
  CHECK_THROWS(sim->stability(), InvalidInput);  // implicit: no explicit stability limit
  CHECK_THROWS(integrator_from_name("rk4"), InvalidInput);
}

TEST(reset_repeats_a_fresh_run_and_keeps_fixed_nodes_and_gravity) {
  for (const auto& name : integrator_names()) {
    auto sim = beam(integrator_from_name(name));
    sim->external_forces().col(0) = Vec3(1, 2, 3);
    sim->step(4);
    sim->reset();
    CHECK(sim->time() == 0.0 && sim->stats().steps == 0);
    CHECK((sim->positions() - sim->model().rest_positions()).norm() == 0.0);
    CHECK(sim->velocities().norm() == 0.0 && sim->external_forces().norm() == 0.0);
    CHECK(!sim->fixed_nodes().empty() && sim->gravity().z() == -9.81);
    sim->step(3);
    auto fresh = beam(integrator_from_name(name));
    fresh->step(3);
    CHECK((sim->positions() - fresh->positions()).norm() == 0.0);
  }
}

TEST(a_claimed_simulation_refuses_every_mutating_call) {
  auto sim = beam(IntegratorKind::Linearized);
  {
    const Simulation::Claim claim(*sim, "a test");
    CHECK_THROWS(sim->step(1), SimulationBusy);
    CHECK_THROWS(sim->set_gravity(Vec3::Zero()), SimulationBusy);
    CHECK_THROWS(sim->set_fixed_nodes({}), SimulationBusy);
    CHECK_THROWS(sim->set_settings(sim->settings()), SimulationBusy);
    CHECK_THROWS(sim->set_solver(std::make_unique<PCG>()), SimulationBusy);
    CHECK_THROWS(sim->reset(), SimulationBusy);
    CHECK_THROWS(sim->solve_static({}), SimulationBusy);
    CHECK_THROWS(sim->attach({0}, Nodes::Zero(3, 1), Vec::Ones(1)), SimulationBusy);
    CHECK_THROWS(sim->move_attachments({0}, Nodes::Zero(3, 1)), SimulationBusy);
    CHECK_THROWS(sim->detach({0}), SimulationBusy);
    CHECK_THROWS(sim->detach_all(), SimulationBusy);
    try {
      sim->step(1);
    } catch (const SimulationBusy& e) {
      CHECK(std::string(e.what()).find("the simulation is busy: step called from another thread") != std::string::npos);
    }
  }
  sim->step(1);  // released
  CHECK(sim->stats().steps == 1);
}

TEST(an_interruption_between_steps_restores_the_state) {
  auto sim = beam(IntegratorKind::Linearized);
  sim->step(2);
  const Nodes x = sim->positions();
  const double t = sim->time();
  int calls = 0;
  CHECK_THROWS(sim->step(10,
                         [&calls](int done) {
                           CHECK(done == calls + 1);
                           if (++calls == 3) throw std::runtime_error("interrupted");
                         }),
               std::runtime_error);
  CHECK(calls == 3 && sim->time() == t && sim->stats().steps == 2);
  CHECK((sim->positions() - x).norm() == 0.0);
  std::vector<int> reported;
  sim->step(3, [&reported](int done) { reported.push_back(done); });
  CHECK((reported == std::vector<int>{1, 2, 3}) && sim->stats().steps == 5);  // the last step reports too
}

TEST(fixed_dofs_project_exactly_the_rows_and_columns_of_fixed_dofs) {
  // Built from the fixed nodes' rows only, the projection must equal the definition: every
  // entry in a fixed row or column zero, a fixed diagonal entry one, the rest untouched.
  const auto mesh = fixtures::tet_beam(3, 2, 2);
  const BlockSparseMatrix pattern = BlockSparseMatrix::from_cells(mesh.points.cols(), mesh.cells);
  std::vector<char> flags(pattern.num_dofs(), 0);
  for (Index d = 0; d < pattern.num_dofs(); ++d) flags[d] = fixtures::uniform() > 0.6;
  BlockSparseMatrix A = pattern;
  for (double& v : A.values()) v = fixtures::uniform(1, 2);
  const BlockSparseMatrix before = A;
  FixedDofs(pattern, flags).project(A);
  const auto& start = pattern.row_start();
  const auto& cols = pattern.columns();
  int wrong = 0;
  for (Index i = 0; i < pattern.num_nodes(); ++i)
    for (int k = start[i]; k < start[i + 1]; ++k)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const Index row = 3 * i + r, col = 3 * cols[k] + c;
          const double expected =
              (flags[row] || flags[col]) ? (row == col ? 1.0 : 0.0) : before.values()[9 * k + 3 * r + c];
          wrong += A.values()[9 * k + 3 * r + c] != expected;
        }
  CHECK(wrong == 0);
}

TEST(attachments_are_part_of_every_integrator_and_restored_with_a_failed_step) {
  // A stiff spring pulls the free end's first node to a target: every integrator ends near it
  // (damped), and a failing call leaves the state and the springs as they were.
  for (const auto& name : integrator_names()) {
    auto sim = beam(integrator_from_name(name));
    sim->set_gravity(Vec3::Zero());
    IntegratorSettings s = sim->settings();
    s.mass_damping = 20;
    sim->set_settings(s);
    const Index node = sim->num_nodes() - 1;
    const Vec3 target = sim->positions().col(node) + Vec3(0, 0, 0.05);
    const double k = 1e8;  // far stiffer than the beam at its tip
    sim->attach({node}, target, Vec::Constant(1, k));
    CHECK_THROWS(sim->attach({node}, Nodes::Constant(3, 1, NAN), Vec::Constant(1, k)), InvalidInput);
    CHECK_THROWS(sim->attach({node}, target, Vec::Constant(1, -k)), InvalidInput);
    CHECK(sim->attachments().size() == 1 && sim->attachments().targets().col(0) == target);
    sim->step(is_explicit(sim->settings().kind) ? 2000 : 200);
    CHECK((sim->positions().col(node) - target).norm() < 1e-3 * 0.05);
    sim->velocities().col(0) = Vec3::Constant(NAN);
    const Nodes x = sim->positions();
    CHECK_THROWS(sim->step(1), InvalidInput);
    CHECK(sim->positions() == x && sim->attachments().size() == 1);
    sim->velocities().col(0).setZero();
    sim->detach({node});
    CHECK(sim->attachments().empty());
    CHECK_THROWS(sim->detach({node}), InvalidInput);
  }
}
