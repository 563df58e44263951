// The floating frame's inertia (modal/floating_frame_inertia.hpp): its mass matrix equals the
// one summed node by node, and its quadratic velocity forces are the right ones: a free,
// undamped flexible body integrated with them keeps its energy, linear momentum and angular
// momentum (a sign or a factor wrong anywhere breaks one of the three at once).
#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "corotate/materials/determinant_derivatives.hpp"
#include "corotate/modal/floating_frame_body.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

struct FlexibleBody {
  Nodes X;
  Eigen::SparseMatrix<double> node_mass;
  Eigen::MatrixXd basis, modal_stiffness;
};

// A small tet beam with its consistent node mass, a random basis of r modes and a random SPD
// modal stiffness (the test is about inertia: any basis will do).
FlexibleBody flexible_body(Index r) {
  const auto mesh = fixtures::tet_beam(3, 1, 1);
  FlexibleBody b;
  b.X = mesh.points;
  const Index n = b.X.cols();
  std::vector<Eigen::Triplet<double>> t;
  for (Index e = 0; e < mesh.cells.rows(); ++e) {
    Eigen::Matrix<double, 3, 4> Xe;
    for (int a = 0; a < 4; ++a) Xe.col(a) = b.X.col(mesh.cells(e, a));
    const auto em = compute_element_matrices<Tet4>(Xe, Material{1e6, 0.3, 1000.0}, e);
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 4; ++c) t.emplace_back(mesh.cells(e, a), mesh.cells(e, c), em.mass(a, c));
  }
  b.node_mass.resize(n, n);
  b.node_mass.setFromTriplets(t.begin(), t.end());
  b.basis = 0.1 * fixtures::random_matrix<Eigen::MatrixXd>(3 * n, r);
  const Eigen::MatrixXd G = fixtures::random_matrix<Eigen::MatrixXd>(r, r);
  b.modal_stiffness = 50.0 * (G * G.transpose() + Eigen::MatrixXd::Identity(r, r));
  return b;
}

// Node velocities (in the frame) from w = (v, omega, eta): v - [u_i]x omega + Psi_i eta.
Eigen::MatrixXd velocity_map(const FlexibleBody& b, const Vec& zeta) {
  const Index n = b.X.cols(), r = b.basis.cols();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(3 * n, 6 + r);
  const Vec u = Eigen::Map<const Vec>(b.X.data(), 3 * n) + b.basis * zeta;
  for (Index i = 0; i < n; ++i) {
    G.block<3, 3>(3 * i, 0) = Mat3::Identity();
    G.block<3, 3>(3 * i, 3) = -cross_matrix(u.segment<3>(3 * i));
    G.block(3 * i, 6, 3, r) = b.basis.middleRows(3 * i, 3);
  }
  return G;
}

}  // namespace

TEST(floating_frame_mass_matrix_is_the_node_by_node_sum) {
  const Index r = 4;
  const FlexibleBody b = flexible_body(r);
  const FloatingFrameInertia inertia(b.X, b.node_mass, b.basis);
  const Eigen::MatrixXd node_mass = Eigen::MatrixXd(b.node_mass);
  Eigen::MatrixXd full_mass = Eigen::MatrixXd::Zero(3 * node_mass.rows(), 3 * node_mass.cols());
  for (Index i = 0; i < node_mass.rows(); ++i)
    for (Index j = 0; j < node_mass.cols(); ++j)
      full_mass.block<3, 3>(3 * i, 3 * j) = node_mass(i, j) * Mat3::Identity();
  for (int trial = 0; trial < 3; ++trial) {
    const Vec zeta = trial == 0 ? Vec(Vec::Zero(r)) : Vec(fixtures::random_matrix<Vec>(r, 1));
    Eigen::MatrixXd M;
    inertia.mass_matrix(zeta, M);
    const Eigen::MatrixXd G = velocity_map(b, zeta);
    const Eigen::MatrixXd expected = G.transpose() * full_mass * G;
    CHECK((M - expected).norm() <= 1e-12 * expected.norm());
  }
  CHECK(std::abs(inertia.mass() - Eigen::MatrixXd(b.node_mass).sum()) <= 1e-12 * inertia.mass());
  CHECK_THROWS(FloatingFrameInertia(b.X, b.node_mass, b.basis.topRows(6)), InvalidInput);
}

namespace {

struct FrameState {
  Vec3 p;
  Mat3 R;
  Vec zeta, w;
  FrameState axpy(double h, const FrameState& d) const {
    return {p + h * d.p, R + h * d.R, zeta + h * d.zeta, w + h * d.w};
  }
};

// The free body's equations: p' = R v, R' = R [omega]x, zeta' = eta, M w' = f_qv - K zeta.
FrameState rate(const FloatingFrameInertia& inertia, const Eigen::MatrixXd& K, const FrameState& s) {
  const Index r = inertia.num_modes();
  Eigen::MatrixXd M;
  inertia.mass_matrix(s.zeta, M);
  Vec f;
  inertia.quadratic_velocity_forces(s.zeta, s.w, f);
  f.tail(r) -= K * s.zeta;
  return {s.R * s.w.segment<3>(0), s.R * cross_matrix(s.w.segment<3>(3)), s.w.tail(r), M.ldlt().solve(f)};
}

}  // namespace

TEST(free_flexible_body_keeps_energy_and_momenta) {
  const Index r = 3;
  const FlexibleBody b = flexible_body(r);
  const FloatingFrameInertia inertia(b.X, b.node_mass, b.basis);
  const Eigen::MatrixXd& K = b.modal_stiffness;
  FrameState s{Vec3(0.3, -0.2, 0.1), Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix(),
               0.05 * fixtures::random_matrix<Vec>(r, 1), Vec(6 + r)};
  s.w << 0.5, -1.0, 0.3, 2.0, -1.5, 3.0, fixtures::random_matrix<Vec>(r, 1);
  auto invariants = [&](const FrameState& x, double& energy, Vec3& linear, Vec3& angular) {
    Eigen::MatrixXd M;
    inertia.mass_matrix(x.zeta, M);
    const Vec pi = M * x.w;
    energy = 0.5 * x.w.dot(pi) + 0.5 * x.zeta.dot(K * x.zeta);
    linear = x.R * pi.segment<3>(0);
    angular = x.p.cross(linear) + x.R * pi.segment<3>(3);
  };
  double e0, e1;
  Vec3 l0, l1, h0, h1;
  invariants(s, e0, l0, h0);
  const double h = 2e-4;
  for (int step = 0; step < 2000; ++step) {  // classical Runge-Kutta: its error is O(h^4)
    const FrameState k1 = rate(inertia, K, s), k2 = rate(inertia, K, s.axpy(h / 2, k1)),
                     k3 = rate(inertia, K, s.axpy(h / 2, k2)), k4 = rate(inertia, K, s.axpy(h, k3));
    s = s.axpy(h / 6, k1).axpy(h / 3, k2).axpy(h / 3, k3).axpy(h / 6, k4);
  }
  invariants(s, e1, l1, h1);
  CHECK(std::abs(e1 - e0) <= 1e-9 * e0);
  CHECK((l1 - l0).norm() <= 1e-9 * l0.norm());
  CHECK((h1 - h0).norm() <= 1e-9 * h0.norm());
  // and the motion was not trivial: the frame turned and the modes moved
  CHECK((s.R - Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix()).norm() > 0.1);
}

TEST(floating_frame_velocity_forces_match_the_mass_matrix_derivatives) {
  // Boltzmann-Hamel from the mass matrix alone, by central differences: f = -M' w - (omega x
  // pi_v, omega x pi_w + v x pi_v, 0) + (0, 0, dT/dzeta). This pins the terms that do no work
  // (a gyroscopic term of the modes), which the conservation test cannot see.
  const Index r = 3;
  const FlexibleBody b = flexible_body(r);
  const FloatingFrameInertia inertia(b.X, b.node_mass, b.basis);
  const Vec zeta = 0.1 * fixtures::random_matrix<Vec>(r, 1);
  Vec w(6 + r);
  w << 0.5, -1.0, 0.3, 2.0, -1.5, 3.0, fixtures::random_matrix<Vec>(r, 1);
  const Vec eta = w.tail(r);
  const double eps = 1e-5;
  Eigen::MatrixXd M, Mp, Mm;
  inertia.mass_matrix(zeta, M);
  inertia.mass_matrix(zeta + eps * eta, Mp);
  inertia.mass_matrix(zeta - eps * eta, Mm);
  const Vec pi = M * w;
  Vec expected = -((Mp - Mm) / (2 * eps)) * w;
  expected.segment<3>(0) -= w.segment<3>(3).cross(pi.segment<3>(0));
  expected.segment<3>(3) -= w.segment<3>(3).cross(pi.segment<3>(3)) + w.segment<3>(0).cross(pi.segment<3>(0));
  for (Index k = 0; k < r; ++k) {
    Vec step = Vec::Zero(r);
    step[k] = eps;
    inertia.mass_matrix(zeta + step, Mp);
    inertia.mass_matrix(zeta - step, Mm);
    expected[6 + k] += 0.5 * w.dot((Mp - Mm) * w) / (2 * eps);
  }
  Vec f;
  inertia.quadratic_velocity_forces(zeta, w, f);
  CHECK((f - expected).norm() <= 1e-8 * expected.norm());
}

TEST(floating_frame_velocity_derivatives_match_finite_differences) {
  // The step's Jacobian: d(M(zeta) w)/dzeta and d(dT/dzeta)/d(w, zeta), by central differences.
  const Index r = 3;
  const FlexibleBody b = flexible_body(r);
  const FloatingFrameInertia inertia(b.X, b.node_mass, b.basis);
  const Vec zeta = 0.1 * fixtures::random_matrix<Vec>(r, 1);
  Vec w(6 + r);
  w << 0.5, -1.0, 0.3, 2.0, -1.5, 3.0, fixtures::random_matrix<Vec>(r, 1);
  Eigen::MatrixXd dmomentum, dgradient_dw, dgradient_dzeta;
  inertia.velocity_derivatives(zeta, w, dmomentum, dgradient_dw, dgradient_dzeta);
  const double eps = 1e-6;
  Eigen::MatrixXd Mp, Mm, expected_momentum(6 + r, r), expected_dzeta(r, r), expected_dw(r, 6 + r);
  Vec gp, gm;
  for (Index k = 0; k < r; ++k) {
    Vec step = Vec::Zero(r);
    step[k] = eps;
    inertia.mass_matrix(zeta + step, Mp);
    inertia.mass_matrix(zeta - step, Mm);
    expected_momentum.col(k) = (Mp - Mm) * w / (2 * eps);
    inertia.kinetic_energy_gradient(zeta + step, w, gp);
    inertia.kinetic_energy_gradient(zeta - step, w, gm);
    expected_dzeta.col(k) = (gp - gm) / (2 * eps);
  }
  for (Index j = 0; j < 6 + r; ++j) {
    Vec step = Vec::Zero(6 + r);
    step[j] = eps;
    inertia.kinetic_energy_gradient(zeta, w + step, gp);
    inertia.kinetic_energy_gradient(zeta, w - step, gm);
    expected_dw.col(j) = (gp - gm) / (2 * eps);
  }
  CHECK((dmomentum - expected_momentum).norm() <= 1e-7 * expected_momentum.norm());
  CHECK((dgradient_dw - expected_dw).norm() <= 1e-7 * expected_dw.norm());
  CHECK((dgradient_dzeta - expected_dzeta).norm() <= 1e-7 * expected_dzeta.norm());
}

namespace {

FloatingFrameState spinning_state(const FloatingFrameBody& body) {
  const Index r = body.inertia().num_modes();
  FloatingFrameState s = body.rest_state();
  s.position = Vec3(0.3, -0.2, 0.1);
  s.rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  s.zeta = 0.05 * fixtures::random_matrix<Vec>(r, 1);
  s.velocity << 0.5, -1.0, 0.3, 2.0, -1.5, 3.0, fixtures::random_matrix<Vec>(r, 1);
  return s;
}

}  // namespace

TEST(floating_frame_step_keeps_momenta_to_round_off_and_energy_bounded) {
  const Index r = 4;
  const FlexibleBody b = flexible_body(r);
  FloatingFrameBody body(FloatingFrameInertia(b.X, b.node_mass, b.basis), b.modal_stiffness);
  FloatingFrameState s = spinning_state(body);
  const double e0 = body.energy(s);
  const Vec3 l0 = body.linear_momentum(s), h0 = body.angular_momentum(s);
  double worst_energy = 0.0;
  int iterations = 0;
  for (int step = 0; step < 1000; ++step) {
    iterations += body.step(s, 1e-2).iterations;
    worst_energy = std::max(worst_energy, std::abs(body.energy(s) - e0) / e0);
  }
  const double dl = (body.linear_momentum(s) - l0).norm() / l0.norm();
  const double dh = (body.angular_momentum(s) - h0).norm() / h0.norm();
  // Each step solves its balances to 1e-14 of the step's momenta and impulses: 1,000 steps.
  CHECK(dl <= 5e-11 && dh <= 5e-11);
  CHECK(worst_energy < 1e-3);         // the bound over 1,000 steps
  std::printf(
      "  free body, 1,000 steps of 10 ms: momenta within %.1e, %.1e; energy within %.2e; %.1f iterations/step\n", dl,
      dh, worst_energy, iterations / 1000.0);
  CHECK((s.rotation.transpose() * s.rotation - Mat3::Identity()).norm() < 1e-12);
}

TEST(floating_frame_body_falls_with_g_whatever_it_does) {
  // Under gravity the linear momentum grows by m g t exactly (the centre of mass falls with
  // g), spinning and vibrating or not; the energy (with the potential) stays bounded.
  const Index r = 3;
  const FlexibleBody b = flexible_body(r);
  FloatingFrameBody body(FloatingFrameInertia(b.X, b.node_mass, b.basis), b.modal_stiffness);
  const Vec3 g(0, 0, -9.81);
  body.set_gravity(g);
  FloatingFrameState s = spinning_state(body);
  const Vec3 l0 = body.linear_momentum(s);
  const double e0 = body.energy(s), h = 5e-3;
  double worst_energy = 0.0;
  for (int step = 0; step < 400; ++step) {
    body.step(s, h);
    worst_energy = std::max(worst_energy, std::abs(body.energy(s) - e0));
  }
  const Vec3 expected = l0 + body.inertia().mass() * g * (400 * h);
  CHECK((body.linear_momentum(s) - expected).norm() <= 1e-11 * expected.norm());
  CHECK(worst_energy < 1e-3 * std::abs(body.inertia().mass() * g.norm() * 2.0));  // vs m g (2 m of fall)
}

TEST(floating_frame_step_refuses_bad_input_and_keeps_the_state) {
  const FlexibleBody b = flexible_body(2);
  FloatingFrameBody body(FloatingFrameInertia(b.X, b.node_mass, b.basis), b.modal_stiffness);
  FloatingFrameState s = spinning_state(body);
  const FloatingFrameState before = s;
  CHECK_THROWS(body.step(s, 0.0), InvalidInput);
  CHECK_THROWS(body.step(s, std::nan("")), InvalidInput);
  s.velocity[7] = std::nan("");
  CHECK_THROWS(body.step(s, 1e-2), InvalidInput);
  s = before;
  s.rotation(0, 0) += 0.1;  // not a rotation
  CHECK_THROWS(body.step(s, 1e-2), InvalidInput);
  s = before;
  body.step(s, 1e-2);
  CHECK(s.zeta != before.zeta);
  CHECK_THROWS(FloatingFrameBody(FloatingFrameInertia(b.X, b.node_mass, b.basis), Eigen::MatrixXd::Identity(3, 3)),
               InvalidInput);
}

TEST(spherical_support_keeps_the_vertical_angular_momentum_about_its_point) {
  // A flexible body hanging from a spherical joint at its frame's origin, spinning and
  // swinging under gravity: the moment about the vertical through the joint is zero, so that
  // component of the angular momentum about the joint is kept to round-off; the energy
  // (with the potential) stays bounded.
  const FlexibleBody b = flexible_body(3);
  FloatingFrameBody body(FloatingFrameInertia(b.X, b.node_mass, b.basis), b.modal_stiffness);
  body.set_gravity(Vec3(0, 0, -9.81));
  body.set_support(FrameSupport::Spherical);
  FloatingFrameState s = spinning_state(body);
  s.velocity.head<3>().setZero();
  auto vertical_momentum = [&](const FloatingFrameState& x) {
    return (body.angular_momentum(x) - x.position.cross(body.linear_momentum(x))).z();
  };
  const double h0 = vertical_momentum(s), e0 = body.energy(s);
  const Vec3 p0 = s.position;
  double worst_energy = 0.0;
  for (int step = 0; step < 500; ++step) {
    body.step(s, 5e-3);
    worst_energy = std::max(worst_energy, std::abs(body.energy(s) - e0) / std::abs(e0));
  }
  CHECK(std::abs(vertical_momentum(s) - h0) <= 1e-11 * std::abs(h0));
  CHECK(s.position == p0);
  CHECK(worst_energy < 1e-3);
  // A state whose origin moves is refused.
  s.velocity[0] = 1.0;
  CHECK_THROWS(body.step(s, 5e-3), InvalidInput);
}

TEST(revolute_support_swings_a_stiff_body_as_the_rigid_compound_pendulum) {
  // The modes made very stiff: the body swings about the frame's z axis (gravity along -y)
  // as a rigid pendulum, theta'' = a . ((R(theta) c) x g) / (a . J a), integrated finely.
  const FlexibleBody b = flexible_body(2);
  const Eigen::MatrixXd stiff = 1e9 * b.modal_stiffness;
  FloatingFrameBody body(FloatingFrameInertia(b.X, b.node_mass, b.basis), stiff);
  const Vec3 g(0, -9.81, 0);
  body.set_gravity(g);
  body.set_support(FrameSupport::Revolute, Vec3::UnitZ());
  FloatingFrameState s = body.rest_state();
  const Vec3 c = body.inertia().first_moment(s.zeta);
  const double inertia_z = body.inertia().inertia(s.zeta)(2, 2);
  auto acceleration = [&](double theta) {
    return (Eigen::AngleAxisd(theta, Vec3::UnitZ()).toRotationMatrix() * c).cross(g).z() / inertia_z;
  };
  double theta = 0.0, rate = 0.0;
  const double dt = 1e-4;
  for (int step = 0; step < 10000; ++step) {  // 1 s, Runge-Kutta
    const double k1 = rate, l1 = acceleration(theta), k2 = rate + dt / 2 * l1, l2 = acceleration(theta + dt / 2 * k1),
                 k3 = rate + dt / 2 * l2, l3 = acceleration(theta + dt / 2 * k2), k4 = rate + dt * l3,
                 l4 = acceleration(theta + dt * k3);
    theta += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    rate += dt / 6 * (l1 + 2 * l2 + 2 * l3 + l4);
  }
  for (int step = 0; step < 1000; ++step) body.step(s, 1e-3);
  const double angle = std::atan2(s.rotation(1, 0), s.rotation(0, 0));
  CHECK(std::abs(theta) > 0.3);  // it swung
  CHECK(std::abs(angle - theta) < 1e-3 * std::abs(theta));
  CHECK((s.rotation * Vec3::UnitZ() - Vec3::UnitZ()).norm() < 1e-12);  // about its axis only
}

TEST(held_body_jacobian_carries_the_loads_turn_with_the_frame) {
  // A soft body swinging on a revolute joint under gravity and a node load (fixed in the world,
  // then turning with the body): the loads turn in the frame as it swings, and the step's
  // Jacobian carries that (loads_turn). With it, the first correction after a fresh factor cuts
  // the residual about as Newton's does (measured: by 4e-6 or more); without it, by 1.8e-4.
  const FlexibleBody b = flexible_body(3);
  for (const LoadFrame frame : {LoadFrame::World, LoadFrame::Body}) {
    FloatingFrameBody body(FloatingFrameInertia(b.X, b.node_mass, b.basis), b.modal_stiffness);
    body.set_gravity(Vec3(0, -9.81, 0));
    body.set_support(FrameSupport::Revolute, Vec3::UnitZ());
    const Index node = b.X.cols() - 1;
    Nodes point = b.X.col(node), force(3, 1);
    force << 30.0, -20.0, 5.0;
    body.set_node_loads(point, b.basis.middleRows(3 * node, 3), force, frame);
    FloatingFrameState s = body.rest_state();
    double worst = 0.0;
    int fresh = 0;
    for (int step = 0; step < 300; ++step) {
      const FloatingFrameStepStats stats = body.step(s, 1e-2);
      if (stats.fresh_rate > 0.0) worst = std::max(worst, stats.fresh_rate), ++fresh;
    }
    CHECK(std::abs(std::atan2(s.rotation(1, 0), s.rotation(0, 0))) > 0.3);  // it swung
    CHECK(fresh > 0);
    CHECK(worst < 1e-5);
  }
}

TEST(prescribed_frame_motion_gives_the_modes_of_the_jointed_body_that_moved_so) {
  // A body on a spherical joint, its frame motion recorded and then prescribed to a twin: the
  // twin's modes follow the first body's to the solver's tolerance (the same modal balance,
  // the frame's inertial loads, centrifugal, Coriolis and Euler, entering as prescribed).
  const FlexibleBody b = flexible_body(3);
  FloatingFrameBody free_body(FloatingFrameInertia(b.X, b.node_mass, b.basis), b.modal_stiffness);
  FloatingFrameBody driven(FloatingFrameInertia(b.X, b.node_mass, b.basis), b.modal_stiffness);
  free_body.set_gravity(Vec3(0, 0, -9.81));
  driven.set_gravity(Vec3(0, 0, -9.81));
  free_body.set_support(FrameSupport::Spherical);
  FloatingFrameState s = spinning_state(free_body);
  s.velocity.head<3>().setZero();
  FloatingFrameState twin = s;
  double worst = 0.0, largest = 0.0;
  for (int step = 0; step < 300; ++step) {
    free_body.step(s, 5e-3);
    FramePose pose;
    pose.position = s.position, pose.rotation = s.rotation;
    pose.velocity = s.velocity.head<3>(), pose.angular_velocity = s.velocity.segment<3>(3);
    driven.step_prescribed(twin, 5e-3, pose);
    worst = std::max(worst, (twin.zeta - s.zeta).norm());
    largest = std::max(largest, s.zeta.norm());
  }
  CHECK(worst <= 1e-10 * largest);
  CHECK(twin.rotation == s.rotation && twin.position == s.position);
  FramePose bad;
  bad.angular_velocity[1] = std::nan("");
  const FloatingFrameState before = twin;
  CHECK_THROWS(driven.step_prescribed(twin, 5e-3, bad), InvalidInput);
  CHECK(twin.zeta == before.zeta);
}
