// Every registered force model through the one evaluate() entry point: forces are -dE/dx,
// the exact tangent is -df/dx, linearised forces are f(x) - K(x)(y - x), the answers do not
// depend on call order, and a clone answers the same. Central differences at a large,
// rotated deformation; the models and cell types come from the factory's own name lists.
#include <cmath>

#include "corotate/models/model_factory.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;
using fixtures::uniform;

namespace {

// 2 x 1 x 1 hexahedra (VTK order) on the unit lattice.
fixtures::Mesh hex_beam() {
  fixtures::Mesh m;
  m.points.resize(3, 12);
  int n = 0;
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= 1; ++j)
      for (int i = 0; i <= 2; ++i) m.points.col(n++) = Vec3(i, j, k);
  auto id = [](int i, int j, int k) { return k * 6 + j * 3 + i; };
  m.cells.resize(2, 8);
  for (int c = 0; c < 2; ++c) {
    const int corner[8] = {id(c, 0, 0), id(c + 1, 0, 0), id(c + 1, 1, 0), id(c, 1, 0),
                           id(c, 0, 1), id(c + 1, 0, 1), id(c + 1, 1, 1), id(c, 1, 1)};
    for (int a = 0; a < 8; ++a) m.cells(c, a) = corner[a];
  }
  return m;
}

fixtures::Mesh mesh_for(const std::string& cell_type) {
  if (cell_type == "hexahedron") return hex_beam();
  return fixtures::tet_beam(2, 1, 1);
}

Nodes deformed(const Nodes& X) {  // a rotation by ~60 degrees plus 5 % random strain
  const Mat3 R = Eigen::AngleAxisd(1.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Nodes x = X;
  for (Index i = 0; i < X.cols(); ++i) x.col(i) = R * (X.col(i) + 0.05 * Vec3(uniform(), uniform(), uniform()));
  return x;
}

Nodes forces(ForceModel& model, const Nodes& x) {
  Nodes f = Nodes::Zero(3, x.cols());
  model.add_forces(x, f);
  return f;
}

Vec stiffness_times(ForceModel& model, const Nodes& x, StiffnessKind kind, const Vec& d) {
  BlockSparseMatrix K = model.pattern();
  K.set_zero();
  model.add_stiffness(x, kind, 1.0, K);
  Vec out(d.size());
  K.multiply(d, out);
  return out;
}

const Material kMaterial{1e6, 0.3, 1000.0};

}  // namespace

TEST(every_model_forces_are_minus_the_energy_gradient) {
  for (const std::string cell : {"tetra", "hexahedron"})
    for (const auto& name : model_names()) {
      // A co-rotated hex's force -R K_e u is not the gradient of 1/2 u^T K_e u: R is the
      // polar rotation at the centre only. Co-rotated tets are conservative (tested).
      if (name == "corotational" && cell != "tetra") continue;
      const auto mesh = mesh_for(cell);
      auto model = make_model(name, cell, mesh.points, mesh.cells, kMaterial);
      const Nodes x = deformed(mesh.points);
      Nodes d(3, x.cols());
      for (Index k = 0; k < d.size(); ++k) d.data()[k] = uniform();
      const double h = 1e-6;
      const double dE = (model->energy(x + h * d) - model->energy(x - h * d)) / (2 * h);
      const double f_d = as_dofs(forces(*model, x)).dot(as_dofs(d));
      if (std::abs(f_d + dE) > 1e-6 * std::abs(dE) + 1e-6) std::printf("    %s on %s\n", name.c_str(), cell.c_str());
      CHECK_NEAR(f_d, -dE, 1e-6 * std::abs(dE) + 1e-6);
    }
}

TEST(exact_tangents_are_minus_the_force_derivative) {
  for (const std::string cell : {"tetra", "hexahedron"})
    for (const auto& name : model_names()) {
      if (name == "corotational" && cell != "tetra") continue;  // hexes: R K R^T, not exact
      const auto mesh = mesh_for(cell);
      auto model = make_model(name, cell, mesh.points, mesh.cells, kMaterial);
      const Nodes x = deformed(mesh.points);
      Nodes d(3, x.cols());
      for (Index k = 0; k < d.size(); ++k) d.data()[k] = uniform();
      const double h = 1e-6;
      const Vec fd = -(as_dofs(forces(*model, x + h * d)) - as_dofs(forces(*model, x - h * d))) / (2 * h);
      const Vec Kd = stiffness_times(*model, x, StiffnessKind::Tangent, as_dofs(d));
      if (!((Kd - fd).norm() <= 1e-6 * fd.norm()))
        std::printf("    %s on %s: %g\n", name.c_str(), cell.c_str(), (Kd - fd).norm() / fd.norm());
      CHECK((Kd - fd).norm() <= 1e-6 * fd.norm());
    }
}

TEST(linearised_forces_are_force_minus_model_stiffness_times_step) {
  for (const std::string cell : {"tetra", "hexahedron"})
    for (const auto& name : model_names()) {
      const auto mesh = mesh_for(cell);
      auto model = make_model(name, cell, mesh.points, mesh.cells, kMaterial);
      const Nodes x = deformed(mesh.points);
      Nodes y = x;
      for (Index k = 0; k < y.size(); ++k) y.data()[k] += 0.01 * uniform();
      Request what;
      what.forces = true;
      what.forces_at = &y;
      Nodes f = Nodes::Zero(3, x.cols());
      Results out;
      out.forces = &f;
      model->evaluate(x, what, out);
      const Vec expected =
          as_dofs(forces(*model, x)) - stiffness_times(*model, x, StiffnessKind::Model, as_dofs(Nodes(y - x)));
      if (!((as_dofs(f) - expected).norm() <= 1e-10 * expected.norm()))
        std::printf("    %s on %s: %g\n", name.c_str(), cell.c_str(), (as_dofs(f) - expected).norm() / expected.norm());
      CHECK((as_dofs(f) - expected).norm() <= 1e-10 * expected.norm());
    }
}

TEST(answers_depend_only_on_the_arguments_and_clones_agree) {
  const auto mesh = fixtures::tet_beam(2, 1, 1);
  for (const auto& name : model_names()) {
    auto model = make_model(name, "tetra", mesh.points, mesh.cells, kMaterial);
    const Nodes x = deformed(mesh.points), other = deformed(mesh.points);
    const Nodes first = forces(*model, x);
    forces(*model, other);  // a call elsewhere in between changes nothing
    auto copy = model->clone();
    CHECK((forces(*model, x) - first).norm() <= 1e-12 * first.norm());
    CHECK((forces(*copy, x) - first).norm() <= 1e-12 * first.norm());
  }
}

TEST(requests_a_model_cannot_answer_are_refused) {
  const auto mesh = fixtures::tet_beam(1, 1, 1);
  auto model = make_model("corotational", "tetra", mesh.points, mesh.cells, kMaterial);
  BlockSparseMatrix K = model->pattern();
  CHECK_THROWS(model->add_stiffness(mesh.points, StiffnessKind::Geometric, 1.0, K), InvalidInput);
  const Nodes wrong = Nodes::Zero(3, 3);
  CHECK_THROWS(model->energy(wrong), InvalidInput);
  CHECK_THROWS(make_model("stvk", "wedge", mesh.points, mesh.cells, kMaterial), InvalidInput);
  CHECK_THROWS(make_model("corotational", "triangle", mesh.points, mesh.cells, kMaterial), InvalidInput);
}
