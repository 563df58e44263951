// Every registered force model through the one evaluate() entry point: forces are -dE/dx,
// the exact tangent is -df/dx, linearised forces are f(x) - K(x)(y - x), the answers do not
// depend on call order, and a clone answers the same. Central differences at a large,
// rotated deformation; the models and cell types come from the factory's own name lists.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "corotate/models/joined_model.hpp"
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

// The same two cells as serendipity Hex20 (VTK order: corners, then the mid-edge nodes of
// the edges below), mid-edge nodes shared between the cells.
fixtures::Mesh hex20_beam() {
  const fixtures::Mesh corners = hex_beam();
  static const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                   {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  std::vector<Vec3> points;
  for (Index i = 0; i < corners.points.cols(); ++i) points.push_back(corners.points.col(i));
  std::map<std::pair<int, int>, int> mid;
  fixtures::Mesh m;
  m.cells.resize(corners.cells.rows(), 20);
  for (Index c = 0; c < corners.cells.rows(); ++c) {
    for (int a = 0; a < 8; ++a) m.cells(c, a) = corners.cells(c, a);
    for (int k = 0; k < 12; ++k) {
      const int p = corners.cells(c, edges[k][0]), q = corners.cells(c, edges[k][1]);
      const auto key = std::minmax(p, q);
      auto it = mid.find(key);
      if (it == mid.end()) {
        it = mid.emplace(key, static_cast<int>(points.size())).first;
        points.push_back(0.5 * (corners.points.col(p) + corners.points.col(q)));
      }
      m.cells(c, 8 + k) = it->second;
    }
  }
  m.points.resize(3, static_cast<Index>(points.size()));
  for (size_t i = 0; i < points.size(); ++i) m.points.col(static_cast<Index>(i)) = points[i];
  return m;
}

fixtures::Mesh mesh_for(const std::string& cell_type) {
  if (cell_type == "hexahedron") return hex_beam();
  if (cell_type == "hexahedron20") return hex20_beam();
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
  // Co-rotated hexes included: their tangent has the polar-rotation derivative and is not
  // symmetric (all blocks assembled); the rotation here is ~60 degrees.
  for (const std::string cell : {"tetra", "hexahedron", "hexahedron20"})
    for (const auto& name : model_names()) {
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

TEST(corotated_hex_tangents_are_not_symmetric_and_say_so) {
  for (const std::string cell : {"tetra", "hexahedron", "hexahedron20"}) {
    const auto mesh = mesh_for(cell);
    auto model = make_model("corotational", cell, mesh.points, mesh.cells, kMaterial);
    CHECK(model->symmetric_tangent() == (cell == "tetra"));
    BlockSparseMatrix K = model->pattern();
    K.set_zero();
    model->add_stiffness(deformed(mesh.points), StiffnessKind::Tangent, 1.0, K);
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> rows;
    K.copy_to(rows);
    const Eigen::MatrixXd dense(rows);
    const double asymmetry = (dense - dense.transpose()).cwiseAbs().maxCoeff() / dense.cwiseAbs().maxCoeff();
    CHECK(cell == "tetra" ? asymmetry < 1e-12 : asymmetry > 1e-3);
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

TEST(a_renamed_model_name_says_the_new_name) {
  const auto mesh = fixtures::tet_beam(1, 1, 1);
  std::string message;
  try {
    make_model("corotated", "tetra", mesh.points, mesh.cells, kMaterial);
  } catch (const InvalidInput& e) {
    message = e.what();
  }
  CHECK(message.find("model 'corotated' was renamed 'fixed_corotated'") == 0);
  const auto names = model_names();
  CHECK(std::find(names.begin(), names.end(), "fixed_corotated") != names.end());
  CHECK(std::find(names.begin(), names.end(), "corotated") == names.end());
  check_renamed_model("fixed_corotated");  // a current name passes
}

TEST(a_body_of_one_region_is_the_homogeneous_body_bit_for_bit) {
  for (const std::string cell : {"tetra", "hexahedron"})
    for (const auto& name : model_names()) {
      const auto mesh = mesh_for(cell);
      const RegionMaterials one_region({kMaterial}, std::vector<int>(mesh.cells.rows(), 0));
      auto homogeneous = make_model(name, cell, mesh.points, mesh.cells, kMaterial);
      auto regions = make_model(name, cell, mesh.points, mesh.cells, one_region);
      const Nodes x = deformed(mesh.points);
      CHECK(forces(*homogeneous, x) == forces(*regions, x));
      CHECK(homogeneous->energy(x) == regions->energy(x));
      BlockSparseMatrix K = homogeneous->pattern(), K_regions = regions->pattern();
      K.set_zero();
      K_regions.set_zero();
      homogeneous->add_stiffness(x, StiffnessKind::Model, 1.0, K);
      regions->add_stiffness(x, StiffnessKind::Model, 1.0, K_regions);
      CHECK(K.values() == K_regions.values());
      CHECK(homogeneous->mass_matrix(false).values() == regions->mass_matrix(false).values());
    }
}

TEST(each_cell_takes_its_regions_stiffness_and_density) {
  // Two materials on alternate tets: the body's forces and lumped masses are the sums of
  // those of one-cell bodies, each of its own cell's material.
  const auto mesh = fixtures::tet_beam(2, 1, 1);
  const Material other{3 * kMaterial.youngs_modulus, 0.1, 2.5 * kMaterial.density};
  const Material by_region[2] = {kMaterial, other};
  std::vector<int> regions(mesh.cells.rows());
  for (Index e = 0; e < mesh.cells.rows(); ++e) regions[e] = static_cast<int>(e % 2);
  const Nodes x = deformed(mesh.points);
  for (const auto& name : model_names()) {
    auto body = make_model(name, "tetra", mesh.points, mesh.cells, RegionMaterials({kMaterial, other}, regions));
    Nodes expected_f = Nodes::Zero(3, x.cols()), expected_m = Nodes::Zero(3, x.cols());
    for (Index e = 0; e < mesh.cells.rows(); ++e) {
      Nodes X(3, 4), xe(3, 4);
      Connectivity cell(1, 4);
      for (int a = 0; a < 4; ++a) {
        X.col(a) = mesh.points.col(mesh.cells(e, a));
        xe.col(a) = x.col(mesh.cells(e, a));
        cell(0, a) = a;
      }
      auto one = make_model(name, "tetra", X, cell, by_region[regions[e]]);
      const Nodes fe = forces(*one, xe);
      const BlockSparseMatrix Me = one->mass_matrix(true);
      for (int a = 0; a < 4; ++a) {
        expected_f.col(mesh.cells(e, a)) += fe.col(a);
        expected_m.col(mesh.cells(e, a)) += Me.block(Me.diagonal_block(a)).diagonal();
      }
    }
    CHECK((forces(*body, x) - expected_f).norm() <= 1e-12 * expected_f.norm());
    const BlockSparseMatrix M = body->mass_matrix(true);
    for (Index i = 0; i < M.num_nodes(); ++i)
      CHECK((Vec3(M.block(M.diagonal_block(i)).diagonal()) - expected_m.col(i)).norm() <=
            1e-12 * expected_m.col(i).norm());
  }
}

TEST(joined_model_is_its_parts_side_by_side) {
  // A co-rotated tet beam and a Neo-Hookean hex beam joined: energy, forces (plain and
  // linearised), every stiffness kind and the mass are each part's at its own nodes, and the
  // joined pattern holds no block between the parts.
  const fixtures::Mesh tets = fixtures::tet_beam(2, 1, 1), hexes = hex_beam();
  auto a = make_model("corotational", "tetra", tets.points, tets.cells, kMaterial);
  auto b = make_model("neohookean", "hexahedron", hexes.points, hexes.cells, Material{2e6, 0.4, 500.0});
  const JoinedModel joined({a.get(), b.get()});
  auto copy = joined.clone();  // a simulation steps a copy
  const Index na = a->num_nodes(), nb = b->num_nodes();
  CHECK(copy->num_nodes() == na + nb);
  CHECK(copy->pattern().num_blocks() == a->pattern().num_blocks() + b->pattern().num_blocks());
  CHECK(copy->pattern().block_index(0, na) == -1 && copy->pattern().block_index(na, 0) == -1);
  CHECK(!copy->is_linear() && copy->symmetric_tangent());
  Nodes x(3, na + nb), y(3, na + nb);
  x << deformed(tets.points), deformed(hexes.points);
  y << deformed(tets.points), deformed(hexes.points);
  const Nodes xa = x.leftCols(na), xb = x.rightCols(nb);
  CHECK(std::abs(copy->energy(x) - (a->energy(xa) + b->energy(xb))) <= 1e-12 * std::abs(copy->energy(x)));
  Nodes f = forces(*copy, x);
  CHECK((f.leftCols(na) - forces(*a, xa)).norm() <= 1e-12 * f.norm());
  CHECK((f.rightCols(nb) - forces(*b, xb)).norm() <= 1e-12 * f.norm());
  for (const StiffnessKind kind : {StiffnessKind::Model, StiffnessKind::Tangent}) {
    const Vec d = fixtures::random_matrix<Vec>(3 * (na + nb), 1);
    const Vec Kd = stiffness_times(*copy, x, kind, d);
    CHECK((Kd.head(3 * na) - stiffness_times(*a, xa, kind, d.head(3 * na))).norm() <= 1e-12 * Kd.norm());
    CHECK((Kd.tail(3 * nb) - stiffness_times(*b, xb, kind, d.tail(3 * nb))).norm() <= 1e-12 * Kd.norm());
  }
  // The implicit step's request: linearised forces at y with the Model stiffness, scaled.
  Request what;
  what.forces = true;
  what.forces_at = &y;
  what.stiffness = StiffnessKind::Model;
  what.stiffness_scale = 0.25;
  what.lower_blocks = false;
  what.count_inverted = true;
  BlockSparseMatrix K = copy->pattern();
  K.set_zero();
  Nodes g = Nodes::Zero(3, na + nb);
  Results out;
  out.forces = &g;
  out.stiffness = &K;
  copy->evaluate(x, what, out);
  for (const auto& [part, offset] : {std::pair<ForceModel*, Index>{a.get(), 0}, {b.get(), na}}) {
    const Index n = part->num_nodes();
    const Nodes xp = x.middleCols(offset, n), yp = y.middleCols(offset, n);
    Request own = what;
    own.forces_at = &yp;
    own.lower_blocks = true;
    BlockSparseMatrix Kp = part->pattern();
    Kp.set_zero();
    Nodes gp = Nodes::Zero(3, n);
    Results part_out;
    part_out.forces = &gp;
    part_out.stiffness = &Kp;
    part->evaluate(xp, own, part_out);
    CHECK((g.middleCols(offset, n) - gp).norm() <= 1e-12 * gp.norm());
    for (Index i = 0; i < n; ++i)
      for (int e = Kp.row_start()[i]; e < Kp.row_start()[i + 1]; ++e)
        CHECK((K.block(K.block_index(offset + i, offset + Kp.columns()[e])) - Kp.block(e)).norm() <=
              1e-12 * Kp.block(e).norm() + 1e-300);
  }
  CHECK(out.inverted == 0);
  const BlockSparseMatrix M = copy->mass_matrix(false), Ma = a->mass_matrix(false), Mb = b->mass_matrix(false);
  const Vec ones = Vec::Ones(3 * (na + nb));
  Vec Mx(ones.size()), Max(3 * na), Mbx(3 * nb);
  M.multiply(ones, Mx);
  Ma.multiply(ones.head(3 * na), Max);
  Mb.multiply(ones.tail(3 * nb), Mbx);
  CHECK((Mx.head(3 * na) - Max).norm() <= 1e-14 * Max.norm() && (Mx.tail(3 * nb) - Mbx).norm() <= 1e-14 * Mbx.norm());
  CHECK_THROWS(JoinedModel(std::vector<const ForceModel*>{}), InvalidInput);
}
