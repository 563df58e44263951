// The modal force polynomial and the modal integrator: the tangent is the derivative of
// the forces (central differences), the forces the gradient of the energy when the
// tensors come from a potential, and a single-mode step reproduces backward Euler's
// known amplification and phase; partial rotation fits a rigid turn exactly and turns by
// half of it.
#include "corotate/modal/modal_basis.hpp"
#include "corotate/modal/modal_integrator.hpp"
#include "corotate/modal/partial_rotation.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

using Mat = Eigen::MatrixXd;
constexpr Index r = 4;

// A (l, k, i) and B (l, k, i, j) fully symmetric: the third and fourth derivatives of a
// random quartic potential, as a reduced StVK body has.
ModalForces random_polynomial_forces() {
  const Mat G = fixtures::random_matrix<Mat>(r, r);
  const Mat K = G * G.transpose() + Mat::Identity(r, r);
  const Vec a = fixtures::random_matrix<Vec>(r * r * r, 1);
  const Vec b = fixtures::random_matrix<Vec>(r * r * r * r, 1);
  Mat A(r * r, r), B(r * r, r * r);
  for (Index l = 0; l < r; ++l)
    for (Index k = 0; k < r; ++k)
      for (Index i = 0; i < r; ++i) {
        A(l + r * k, i) = a[l * k * i % a.size()] + a[(l + k + i) % a.size()];  // symmetric in l, k, i
        for (Index j = 0; j < r; ++j)
          B(l + r * k, i + r * j) = b[(l + k + i + j) % b.size()] + b[(l * k * i * j) % b.size()];
      }
  return ModalForces(K, A, B);
}

// The tangent -df/dq at q by central differences of step h.
Mat central_difference_tangent(ModalForces& forces, const Vec& q, double h) {
  Mat T(r, r);
  Vec fp, fm;
  for (Index j = 0; j < r; ++j) {
    Vec dq = Vec::Zero(r);
    dq[j] = h;
    forces.evaluate(q + dq, fp, nullptr);
    forces.evaluate(q - dq, fm, nullptr);
    T.col(j) = -(fp - fm) / (2 * h);
  }
  return T;
}

}  // namespace

TEST(modal_tangent_is_the_derivative_of_the_forces) {
  ModalForces forces = random_polynomial_forces();
  const Vec q = fixtures::random_matrix<Vec>(r, 1);
  Vec f;
  Mat T;
  forces.evaluate(q, f, &T);
  const double h = 1e-5;
  const Mat fd = central_difference_tangent(forces, q, h);
  for (Index j = 0; j < r; ++j) CHECK_NEAR((fd.col(j) - T.col(j)).norm() / T.col(j).norm(), 0.0, 1e-8);
  // ... and the forces are the gradient of the energy (fully symmetric tensors).
  for (Index j = 0; j < r; ++j) {
    Vec dq = Vec::Zero(r);
    dq[j] = h;
    const double dE = (forces.energy(q + dq) - forces.energy(q - dq)) / (2 * h);
    CHECK_NEAR(-dE, f[j], 1e-7 * f.norm());
  }
}

TEST(modal_tangent_holds_for_unsymmetric_quadratic_tensors) {
  // The mode-based geometric stiffness A_i is not symmetric in its scaling index: the
  // constructor's symmetrisation must leave the forces alone and make T exact.
  const Mat A = fixtures::random_matrix<Mat>(r * r, r);
  ModalForces forces(Mat::Identity(r, r), A, Mat());
  const Vec q = fixtures::random_matrix<Vec>(r, 1);
  Vec f;
  Mat T;
  forces.evaluate(q, f, &T);
  Vec expected = -q;
  for (Index i = 0; i < r; ++i) expected -= 0.5 * q[i] * Eigen::Map<const Mat>(A.col(i).data(), r, r) * q;
  CHECK_NEAR((f - expected).norm(), 0.0, 1e-12 * expected.norm());
  const Mat fd = central_difference_tangent(forces, q, 1e-6);
  for (Index j = 0; j < r; ++j) CHECK_NEAR((fd.col(j) - T.col(j)).norm(), 0.0, 1e-7 * T.norm());
}

TEST(modal_step_is_backward_euler_of_each_mode) {
  // One undamped mode x'' = -w^2 x: backward Euler multiplies (x, v) by the inverse of
  // [[1, -dt], [w^2 dt, 1]] per step; the linearised step is exact for a linear body.
  const double w = 3.0, dt = 0.05;
  Mat K = Mat::Zero(2, 2);
  K(0, 0) = w * w;
  K(1, 1) = 4 * w * w;
  ModalIntegrator integrator(ModalForces(K, Mat(), Mat()), ModalStepSettings{dt, 0.0, 0.0});
  integrator.q << 1.0, 0.0;
  Eigen::Matrix2d step;
  step << 1, -dt, w * w * dt, 1;
  const Eigen::Matrix2d inverse = step.inverse();
  Eigen::Vector2d state(1.0, 0.0);
  for (int k = 0; k < 40; ++k) state = inverse * state;
  integrator.step(40);
  CHECK_NEAR(integrator.q[0], state[0], 1e-12);
  CHECK_NEAR(integrator.v[0], state[1], 1e-12);
  CHECK_NEAR(integrator.q[1], 0.0, 0.0);
  CHECK_NEAR(integrator.time, 40 * dt, 1e-12);
}

TEST(modal_static_solve_finds_the_polynomial_equilibrium) {
  ModalForces forces = random_polynomial_forces();
  ModalIntegrator integrator(forces);
  integrator.p = 0.02 * fixtures::random_matrix<Vec>(r, 1);  // moderate: the random quartic is not convex
  integrator.solve_static(4, 1e-12, 50);
  Vec f;
  forces.evaluate(integrator.q, f, nullptr);
  CHECK_NEAR((f + integrator.p).norm(), 0.0, 1e-11 * integrator.p.norm());
}

TEST(modal_bad_input_leaves_the_state) {
  ModalIntegrator integrator(ModalForces(Mat::Identity(2, 2), Mat(), Mat()));
  integrator.q << 1.0, 2.0;
  integrator.v[0] = std::nan("");
  CHECK_THROWS(integrator.step(1), InvalidInput);
  CHECK_NEAR(integrator.q[0], 1.0, 0.0);
  CHECK_THROWS(ModalForces(Mat::Identity(2, 3), Mat(), Mat()), InvalidInput);
  CHECK_THROWS(ModalForces(Mat::Identity(2, 2), Mat::Zero(3, 2), Mat()), InvalidInput);
  CHECK_THROWS(ModalStepSettings({-1.0, 0.0, 0.0}).validate(), InvalidInput);
  const long long nodes[] = {0, 5};
  CHECK_THROWS(check_node_indices(nodes, 2, 5), InvalidInput);
}

TEST(modal_recovery_and_projection_are_the_basis_products) {
  const RowMatrix Phi = fixtures::random_matrix<Mat>(12, 3);
  const BasisMap basis(Phi.data(), 12, 3);
  const Vec q = fixtures::random_matrix<Vec>(3, 1);
  Vec all(12);
  recover_displacements(basis, q, nullptr, 4, all.data());
  CHECK_NEAR((all - Phi * q).norm(), 0.0, 1e-14);
  const long long nodes[] = {3, 1};
  double some[6];
  recover_displacements(basis, q, nodes, 2, some);
  CHECK_NEAR(some[0], all[9], 1e-15);
  CHECK_NEAR(some[5], all[5], 1e-15);
  const double forces[] = {1, 2, 3, 4, 5, 6};
  Vec p(3);
  project_nodal_forces(basis, nodes, 2, forces, p.data());
  Vec full = Vec::Zero(12);
  full.segment<3>(9) << 1, 2, 3;
  full.segment<3>(3) << 4, 5, 6;
  CHECK_NEAR((p - Phi.transpose() * full).norm(), 0.0, 1e-13);
}

TEST(partial_rotation_fits_a_rigid_turn_and_turns_by_half) {
  // Five nodes; domain 0 = nodes 0-3 (its representative points), node 4 half-weighted.
  Eigen::Matrix<double, 5, 3, Eigen::RowMajor> X;
  X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 2, 1, 0;
  const Mat3 R = Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::Matrix<double, 5, 3, Eigen::RowMajor> u = X * (R.transpose() - Mat3::Identity());  // x -> R x
  const std::vector<long long> nodes = {0, 1, 2, 3, 4};
  const double weights[] = {1, 1, 1, 1, 0.5};
  PartialRotation rotation(X.data(), 5, {{0, 1, 2, 3}}, nodes, weights);
  double points[12];
  for (int i = 0; i < 12; ++i) points[i] = u.data()[i];
  rotation.fit(points);
  CHECK_NEAR((rotation.rotation(0) - R).norm(), 0.0, 1e-14);
  CHECK_NEAR(rotation.rotation_vector(0).norm(), 0.4, 1e-14);
  Eigen::Matrix<double, 5, 3, Eigen::RowMajor> turned = u;
  rotation.rotate(nullptr, 5, turned.data());
  const Vec3 axis = Vec3(1, 2, 3).normalized();
  const Mat3 half = Eigen::AngleAxisd(0.2, axis).toRotationMatrix();
  const Mat3 quarter = Eigen::AngleAxisd(0.1, axis).toRotationMatrix();
  for (int i = 0; i < 4; ++i) CHECK_NEAR((turned.row(i).transpose() - half * u.row(i).transpose()).norm(), 0.0, 1e-14);
  CHECK_NEAR((turned.row(4).transpose() - quarter * u.row(4).transpose()).norm(), 0.0, 1e-14);
  // A subset gives the same rows.
  const long long some[] = {4, 1};
  double two[6] = {u(4, 0), u(4, 1), u(4, 2), u(1, 0), u(1, 1), u(1, 2)};
  rotation.rotate(some, 2, two);
  CHECK_NEAR((Eigen::Map<Vec3>(two) - turned.row(4).transpose()).norm(), 0.0, 1e-15);
  CHECK_NEAR((Eigen::Map<Vec3>(two + 3) - turned.row(1).transpose()).norm(), 0.0, 1e-15);
}

TEST(partial_rotation_rejects_points_that_fix_no_rotation) {
  Eigen::Matrix<double, 4, 3, Eigen::RowMajor> X;
  X << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0;
  const double weights[] = {1.0};
  const std::vector<long long> blended = {0};
  CHECK_THROWS(PartialRotation(X.data(), 4, {{0, 1, 2}}, blended, weights), InvalidInput);  // on one line
  CHECK_THROWS(PartialRotation(X.data(), 4, {{3, 3, 3, 3}}, blended, weights), InvalidInput);  // coincident
  CHECK_THROWS(PartialRotation(X.data(), 4, {{0, 1, 4}}, blended, weights), InvalidInput);     // out of range
  const double too_much[] = {1.5};
  CHECK_THROWS(PartialRotation(X.data(), 4, {{0, 1, 3}}, blended, too_much), InvalidInput);
  PartialRotation fine(X.data(), 4, {{0, 1, 3}}, blended, weights);
  CHECK(fine.n_domains() == 1);
}
