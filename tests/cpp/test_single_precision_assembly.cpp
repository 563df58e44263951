// The implicit step's float32 path: the co-rotated tets' forces and stiffness, the mass, the
// attachment springs and the fixed DOFs assembled straight into the solver's float32 system
// (SinglePrecisionSymmetric::start_assembly, Results::single_stiffness) must give the system
// that the double path assembles and then rounds to float, to float32's rounding, in every
// stored block, including the blocks across row chunks that are stored twice.
#include <cmath>
#include <functional>

#include "corotate/fem/attachments.hpp"
#include "corotate/fem/fixed_dofs.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/pcg.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

const Material kMaterial{1e7, 0.3, 1000.0};

// The system of one implicit step at x, in double (then rounded by assign) or straight in
// float32 into single (whose layout exists already).
struct StepSystem {
  std::unique_ptr<ForceModel> model;
  BlockSparseMatrix mass;
  FixedDofs fixed;
  Attachments attachments;
  double s = 1.02, scale = 1e-4;  // 1 + dt alpha and dt^2 + dt beta

  // Each assembly starts from the same warm start of the rotations (the model's caches),
  // so both paths see the same rotations to the bit. `into` puts the stiffness in one of
  // the two systems.
  void evaluate(const Nodes& x, Nodes& forces, const std::function<void(Results&)>& into) {
    model->restore_caches();
    forces.setZero(3, x.cols());
    Request what;
    what.forces = true;
    what.stiffness = StiffnessKind::Model;
    what.stiffness_scale = scale;
    what.lower_blocks = false;
    what.forces_at = &x;
    Results out;
    out.forces = &forces;
    into(out);
    model->evaluate(x, what, out);
  }
  void assemble_double(const Nodes& x, BlockSparseMatrix& A, Nodes& forces) {
    A.assign_scaled(s, mass, false);
    evaluate(x, forces, [&](Results& out) { out.stiffness = &A; });
    attachments.add_stiffness(scale, A);
    fixed.project(A);
  }
  void assemble_single(const Nodes& x, SinglePrecisionSymmetric& S, Nodes& forces, std::uint64_t version) {
    S.start_assembly(mass, s, version);
    evaluate(x, forces, [&](Results& out) { out.single_stiffness = &S; });
    attachments.add_stiffness(scale, S);
    fixed.project(S);
  }
};

// A turned, bent and jittered 64 x 4 x 4 beam (more than one row chunk of the product).
Nodes deformed(const Nodes& rest) {
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Nodes x = rest;
  for (Index i = 0; i < x.cols(); ++i) {
    const Vec3 p = rest.col(i);
    x.col(i) = R * Vec3(p.x(), p.y() + 0.01 * p.x() * p.x(), p.z()) + 0.02 * fixtures::random_matrix<Vec3>();
  }
  return x;
}

// A PCG that never offers its float32 system: the step then assembles in double and the
// solver makes its float32 copy from that (the path before float32 assembly).
class DoubleAssemblyPCG final : public LinearSolver {
 public:
  explicit DoubleAssemblyPCG(const PCGSettings& settings) : pcg_(settings) {}
  void reset() override { pcg_.reset(); }
  void constraints_changed(const FixedDofs& fixed) override { pcg_.constraints_changed(fixed); }
  void set_geometry(const Nodes& rest) override { pcg_.set_geometry(rest); }
  void set_positions(const Nodes& x) override { pcg_.set_positions(x); }
  SolveStats solve(const BlockSparseMatrix& A, const Vec& b, Vec& x) override { return pcg_.solve(A, b, x); }
  bool needs_lower_blocks() const override { return pcg_.needs_lower_blocks(); }

 private:
  PCG pcg_;
};

// The sagging 48 x 4 x 4 beam of test_parallel, 30 steps with the default PCG settings and
// the two-level preconditioner.
Nodes sagging_beam(std::unique_ptr<LinearSolver> solver) {
  const auto mesh = fixtures::tet_beam(48, 4, 4);
  IntegratorSettings settings;
  settings.time_step = 1e-2;
  Simulation sim(make_model("corotational", "tetra", mesh.points, mesh.cells, kMaterial), settings, std::move(solver));
  sim.set_fixed_nodes(fixtures::nodes_at_x0(mesh));
  sim.set_gravity(Vec3(0, 0, -9.81));
  sim.step(30);
  return sim.positions() - mesh.points;
}

}  // namespace

TEST(float32_assembly_steps_like_the_double_system) {
  PCGSettings settings;
  settings.preconditioner = PreconditionerKind::TwoLevel;
  auto pcg = std::make_unique<PCG>(settings);
  CHECK(pcg->single_precision_target() == nullptr);  // not before the hierarchy is built
  const Nodes direct = sagging_beam(std::move(pcg));
  const Nodes converted = sagging_beam(std::make_unique<DoubleAssemblyPCG>(settings));
  // The same motion to float32's rounding (measured 2.9e-7 of the displacement; the 1 %
  // budget is far larger), but not the same bits: the float32 path was taken.
  CHECK((direct - converted).norm() <= 3e-6 * converted.norm());
  CHECK(direct != converted);
  // A tight tolerance multiplies in double: no float32 system to assemble into.
  settings.tolerance = 1e-6;
  PCG tight(settings);
  CHECK(tight.single_precision_target() == nullptr);
}

namespace {
// cubes: the beam's; 64 x 4 x 4 has more than one row chunk, 61 x 3 x 3 (3,294 tets) ends
// its last chunk with a batch of 14 elements (the vectorised scatter takes lanes eight at
// a time).
void check_float32_assembly(int nx, int ny, int nz, bool several_chunks) {
  const auto mesh = fixtures::tet_beam(nx, ny, nz);
  StepSystem step;
  step.model = make_model("corotational", "tetra", mesh.points, mesh.cells, kMaterial);
  CHECK(step.model->assembles_single_precision());
  const BlockSparseMatrix& pattern = step.model->pattern();
  CHECK((pattern.num_chunks() > 1) == several_chunks);
  step.mass = step.model->mass_matrix(false);
  std::vector<char> fixed(pattern.num_dofs(), 0);
  for (int d = 0; d < 3 * 25; ++d) fixed[d] = 1;  // the nodes at x = 0
  fixed[3 * 200 + 1] = 1;                          // and one DOF inside
  step.fixed = FixedDofs(pattern, fixed);
  step.attachments = Attachments(pattern.num_nodes());
  step.attachments.attach({500, 901}, Nodes::Ones(3, 2), Vec::Constant(2, 3e6));

  const Nodes x = deformed(mesh.points);
  step.model->save_caches();
  BlockSparseMatrix A = pattern;
  Nodes forces_double, forces_single;
  step.assemble_double(x, A, forces_double);
  SinglePrecisionSymmetric rounded, direct;
  rounded.assign(A);
  direct.assign(A);  // the layout and scale; then overwritten by the float32 assembly
  for (int repeat = 0; repeat < 2; ++repeat) {  // the second starts from the kept image of s M
    step.assemble_single(x, direct, forces_single, 1);
    CHECK(forces_single == forces_double);  // the forces do not go through float32
    // Every stored value: the double sum rounded once against a few roundings in float32.
    const float* a = rounded.values();
    const float* b = direct.values();
    double largest = 0, error = 0;
    for (Index v = 0; v < 9 * rounded.num_blocks(); ++v) {
      largest = std::max(largest, double(std::abs(a[v])));
      error = std::max(error, double(std::abs(a[v] - b[v])));
    }
    CHECK(error <= 1e-6 * largest);
    CHECK(error > 0);  // it really is accumulated in float32
    // And so the products.
    const Vec p = fixtures::random_matrix<Vec>(pattern.num_dofs(), 1);
    Vec y_double(pattern.num_dofs()), y_single(pattern.num_dofs());
    A.multiply_symmetric(p, y_double);
    direct.multiply(p, y_single);
    CHECK((y_single - y_double).norm() <= 1e-6 * y_double.norm());
  }
  // A new version of M (another mass, or another s) is converted again.
  step.s = 1.5;
  step.assemble_double(x, A, forces_double);
  step.assemble_single(x, direct, forces_single, 1);  // same version, new s
  Vec p = fixtures::random_matrix<Vec>(pattern.num_dofs(), 1), y_double(p.size()), y_single(p.size());
  A.multiply_symmetric(p, y_double);
  direct.multiply(p, y_single);
  CHECK((y_single - y_double).norm() <= 1e-6 * y_double.norm());
}
}  // namespace

TEST(float32_assembly_gives_the_double_system_rounded) {
  check_float32_assembly(64, 4, 4, true);
  check_float32_assembly(61, 3, 3, false);
}

TEST(float32_assembly_refuses_what_it_cannot_assemble) {
  const auto mesh = fixtures::tet_beam(4, 2, 2);
  auto linear = make_model("linear", "tetra", mesh.points, mesh.cells, kMaterial);
  auto corotated = make_model("corotational", "tetra", mesh.points, mesh.cells, kMaterial);
  CHECK(!linear->assembles_single_precision());
  BlockSparseMatrix A = corotated->pattern();
  A.assign_scaled(1.0, corotated->mass_matrix(false), true);
  SinglePrecisionSymmetric S;
  Nodes forces = Nodes::Zero(3, mesh.points.cols());
  Request what;
  what.forces = true;
  what.stiffness = StiffnessKind::Model;
  what.lower_blocks = false;
  Results out;
  out.forces = &forces;
  out.single_stiffness = &S;
  CHECK_THROWS(corotated->evaluate(mesh.points, what, out), InvalidInput);  // no layout yet
  S.assign(A);
  CHECK_THROWS(linear->evaluate(mesh.points, what, out), InvalidInput);  // not this model
  what.lower_blocks = true;
  CHECK_THROWS(corotated->evaluate(mesh.points, what, out), InvalidInput);  // only product blocks
  what.lower_blocks = false;
  corotated->evaluate(mesh.points, what, out);
  // A starting matrix in another pattern.
  const auto other = fixtures::tet_beam(5, 2, 2);
  auto other_model = make_model("corotational", "tetra", other.points, other.cells, kMaterial);
  CHECK_THROWS(S.start_assembly(other_model->mass_matrix(false), 1.0, 7), InvalidInput);
}
