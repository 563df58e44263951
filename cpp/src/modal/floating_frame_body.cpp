#include "corotate/modal/floating_frame_body.hpp"

#include <cmath>
#include <string>

#include "corotate/materials/determinant_derivatives.hpp"  // cross_matrix

namespace corotate {

FloatingFrameBody::FloatingFrameBody(FloatingFrameInertia inertia, Eigen::MatrixXd stiffness, Eigen::MatrixXd damping)
    : inertia_(std::move(inertia)), stiffness_(std::move(stiffness)), damping_(std::move(damping)) {
  const Index r = inertia_.num_modes();
  if (stiffness_.rows() != r || stiffness_.cols() != r)
    throw InvalidInput("floating frame: the modal stiffness must be " + std::to_string(r) + " x " + std::to_string(r));
  if (damping_.size() == 0) damping_ = Eigen::MatrixXd::Zero(r, r);
  if (damping_.rows() != r || damping_.cols() != r)
    throw InvalidInput("floating frame: the modal damping must be " + std::to_string(r) + " x " + std::to_string(r));
  if (!stiffness_.allFinite() || !damping_.allFinite())
    throw InvalidInput("floating frame: the modal stiffness and damping must be finite");
  gravity_rows_.resize(3, r);
  for (Index k = 0; k < r; ++k) gravity_rows_.col(k) = inertia_.modal_first_moment(k) / inertia_.mass();
}

FloatingFrameState FloatingFrameBody::rest_state() const {
  FloatingFrameState s;
  s.zeta = Vec::Zero(inertia_.num_modes());
  s.velocity = Vec::Zero(6 + inertia_.num_modes());
  return s;
}

void FloatingFrameBody::check(const FloatingFrameState& s) const {
  const Index r = inertia_.num_modes();
  if (s.zeta.size() != r || s.velocity.size() != 6 + r)
    throw InvalidInput("floating frame: a state of " + std::to_string(r) + " modal coordinates and " +
                       std::to_string(6 + r) + " velocities expected");
  if (!s.position.allFinite() || !s.rotation.allFinite() || !s.zeta.allFinite() || !s.velocity.allFinite())
    throw InvalidInput("floating frame: the state is not finite");
  if ((s.rotation.transpose() * s.rotation - Mat3::Identity()).norm() > 1e-9 || s.rotation.determinant() < 0)
    throw InvalidInput("floating frame: the frame's rotation is not a rotation matrix");
}

void FloatingFrameBody::frame_loads(const FloatingFrameState& s, Vec3& force, Vec3& torque,
                                    Eigen::Ref<Vec> modal) const {
  const Index r = inertia_.num_modes();
  const Vec3 g = s.rotation.transpose() * gravity_;
  force = inertia_.mass() * g;
  torque = inertia_.first_moment(s.zeta).cross(g);
  for (Index k = 0; k < r; ++k) modal[k] += g.dot(inertia_.modal_first_moment(k));
  for (Index i = 0; i < load_points_.cols(); ++i) {
    const auto rows = load_rows_.middleRows(3 * i, 3);
    const Vec3 f =
        load_frame_ == LoadFrame::Body ? Vec3(load_forces_.col(i)) : Vec3(s.rotation.transpose() * load_forces_.col(i));
    const Vec3 u = load_points_.col(i) + rows * s.zeta;
    force += f;
    torque += u.cross(f);
    modal.noalias() += rows.transpose() * f;
  }
}

void FloatingFrameBody::balance_at(const FloatingFrameState& s, Balance& b) const {
  const Index r = inertia_.num_modes();
  inertia_.momenta(s.zeta, s.velocity, pi_);
  b.linear = s.rotation * pi_.segment<3>(0);
  b.angular = s.position.cross(b.linear) + s.rotation * pi_.segment<3>(3);
  b.modal_momentum = pi_.tail(r);
  // Loads: gravity and the nodal loads, the elastic and damping forces, and dT/dzeta.
  inertia_.kinetic_energy_gradient(s.zeta, s.velocity, b.modal_load);
  Vec3 force, torque;
  frame_loads(s, force, torque, b.modal_load);
  b.force = s.rotation * force;
  b.torque = s.position.cross(b.force) + s.rotation * torque;
  b.modal_load.noalias() -= stiffness_ * s.zeta;
  b.modal_load.noalias() -= damping_ * s.velocity.tail(r);
}

std::array<double, kInertialLoadCases> FloatingFrameBody::load_coefficients(const FloatingFrameState& s,
                                                                            const Vec3& alpha,
                                                                            const Vec3& acceleration) const {
  return inertial_load_coefficients(s.velocity.segment<3>(3), alpha, acceleration - s.rotation.transpose() * gravity_);
}

std::array<double, kInertialLoadCases> FloatingFrameBody::stiffening_force(const FloatingFrameState& s,
                                                                           const Vec3& alpha, const Vec3& acceleration,
                                                                           Vec& out) {
  const Index r = inertia_.num_modes();
  const auto c = load_coefficients(s, alpha, acceleration);
  // K_geo zeta = sum_c c_c K_c zeta over the cases that are loaded: a body on a joint or
  // driven about one axis has few (a pendulum 4 of the 12), a tumbling one all.
  out.setZero(r);
  for (int k = 0; k < kInertialLoadCases; ++k)
    if (c[k] != 0.0) out.noalias() += (c[k] * stiffening_cases_.middleCols(k * r, r)) * s.zeta;
  return c;
}

void FloatingFrameBody::set_node_loads(Nodes points, Eigen::MatrixXd rows, Nodes forces, LoadFrame frame) {
  const Index m = points.cols(), r = inertia_.num_modes();
  if (forces.cols() != m || rows.rows() != 3 * m || rows.cols() != r)
    throw InvalidInput("floating frame: node loads need as many forces as points and 3 basis rows of " +
                       std::to_string(r) + " modes per point");
  if (!points.allFinite() || !rows.allFinite() || !forces.allFinite())
    throw InvalidInput("floating frame: the node loads must be finite");
  load_points_ = std::move(points);
  load_rows_ = std::move(rows);
  load_forces_ = std::move(forces);
  load_frame_ = frame;
}

void FloatingFrameBody::set_geometric_stiffness(const std::vector<Eigen::MatrixXd>& per_case) {
  const Index r = inertia_.num_modes();
  schedule_.invalidate();
  if (per_case.empty()) {
    stiffening_cases_.resize(0, 0);
    return;
  }
  if (per_case.size() != std::size_t(kInertialLoadCases))
    throw InvalidInput("floating frame: the geometric stiffening needs one matrix per inertial load case (12)");
  Eigen::MatrixXd cases(r, kInertialLoadCases * r);
  for (int k = 0; k < kInertialLoadCases; ++k) {
    if (per_case[k].rows() != r || per_case[k].cols() != r || !per_case[k].allFinite())
      throw InvalidInput("floating frame: load case " + std::to_string(k) + "'s geometric stiffness must be a finite " +
                         std::to_string(r) + " x " + std::to_string(r) + " matrix");
    cases.middleCols(k * r, r) = 0.5 * (per_case[k] + per_case[k].transpose());
  }
  stiffening_cases_ = std::move(cases);
}

void FloatingFrameBody::set_support(FrameSupport support, const Vec3& axis) {
  if (support == FrameSupport::Revolute) {
    if (!axis.allFinite() || !(axis.norm() > 0.0))
      throw InvalidInput("floating frame: a revolute support needs a nonzero, finite axis");
    axis_ = axis.normalized();
  }
  support_ = support;
  schedule_.invalidate();
}

void FloatingFrameBody::check_support(const FloatingFrameState& s) const {
  if (prescribed_ != nullptr || support_ == FrameSupport::Free) return;
  const Vec3 v = s.velocity.segment<3>(0), omega = s.velocity.segment<3>(3);
  const double scale = 1e-12 * (1.0 + omega.norm());
  if (v.norm() > scale)
    throw InvalidInput("floating frame: the frame's origin is held by the support, but its velocity is not zero");
  if (support_ == FrameSupport::Revolute && (omega - omega.dot(axis_) * axis_).norm() > scale)
    throw InvalidInput("floating frame: the angular velocity is not along the revolute support's axis");
}

void FloatingFrameBody::constrain(const FloatingFrameState& s, Vec& w) const {
  (void)s;
  if (prescribed_ != nullptr) {
    w.segment<3>(0) = prescribed_->velocity;
    w.segment<3>(3) = prescribed_->angular_velocity;
    return;
  }
  if (support_ == FrameSupport::Free) return;
  w.segment<3>(0).setZero();
  if (support_ == FrameSupport::Revolute) w.segment<3>(3) = w.segment<3>(3).dot(axis_) * axis_;
}

void FloatingFrameBody::support_maps(const FloatingFrameState& s) {
  // The frame's share of the maps (the modal coordinates pass through both unchanged):
  // frame_velocities_ (6 x f): (v, omega) = frame_velocities_ z_f; frame_projection_ (f x 6):
  // the frame balances without the reactions. The origin p is held, so the angular balance
  // about p is the one about the world origin minus p x the linear one; a revolute support
  // also leaves the moment about its axis (a_w = R a, fixed in the world) alone. A prescribed
  // motion leaves the frame nothing (f = 0).
  if (prescribed_ != nullptr) {
    frame_velocities_.resize(6, 0);
    frame_projection_.resize(0, 6);
    return;
  }
  const bool revolute = support_ == FrameSupport::Revolute;
  const Index f = revolute ? 1 : 3;
  frame_velocities_.setZero(6, f);
  frame_projection_.setZero(f, 6);
  const Mat3 about_p = -cross_matrix(s.position);
  if (revolute) {
    frame_velocities_.block<3, 1>(3, 0) = axis_;
    const Vec3 a = s.rotation * axis_;
    frame_projection_.block<1, 3>(0, 0) = a.transpose() * about_p;
    frame_projection_.block<1, 3>(0, 3) = a.transpose();
  } else {
    frame_velocities_.block<3, 3>(3, 0).setIdentity();
    frame_projection_.block<3, 3>(0, 0) = about_p;
    frame_projection_.block<3, 3>(0, 3).setIdentity();
  }
}

FloatingFrameStepStats FloatingFrameBody::step_prescribed(FloatingFrameState& state, double h, const FramePose& end) {
  if (!end.position.allFinite() || !end.rotation.allFinite() || !end.velocity.allFinite() ||
      !end.angular_velocity.allFinite())
    throw InvalidInput("floating frame: the prescribed pose or velocity is not finite");
  if ((end.rotation.transpose() * end.rotation - Mat3::Identity()).norm() > 1e-9 || end.rotation.determinant() < 0)
    throw InvalidInput("floating frame: the prescribed rotation is not a rotation matrix");
  prescribed_ = &end;
  try {
    const FloatingFrameStepStats stats = step(state, h);
    prescribed_ = nullptr;
    return stats;
  } catch (...) {
    prescribed_ = nullptr;
    throw;
  }
}

FloatingFrameStepStats FloatingFrameBody::advance(FloatingFrameState& state, double h, int n) {
  if (n < 0) throw InvalidInput("floating frame: the number of steps must be >= 0");
  const FloatingFrameState before = state;
  FloatingFrameStepStats stats;
  try {
    for (int k = 0; k < n; ++k) {
      const FloatingFrameStepStats one = step(state, h);
      stats.iterations += one.iterations;
      stats.residual = one.residual;
    }
  } catch (...) {
    state = before;
    throw;
  }
  return stats;
}

void FloatingFrameBody::add_stiffening(const FloatingFrameState& state, double h) {
  // - K_geo zeta in both ends' modal loads, with the step's accelerations of the frame.
  if (!stiffening()) return;
  const Index r = inertia_.num_modes();
  const Vec& w0 = state.velocity;
  const Vec& w1 = trial_.velocity;
  const Vec3 alpha = (w1.segment<3>(3) - w0.segment<3>(3)) / h;
  const Vec3 acceleration = (w1.segment<3>(0) - w0.segment<3>(0)) / h +
                            0.25 * (w0.segment<3>(3) + w1.segment<3>(3)).cross(w0.segment<3>(0) + w1.segment<3>(0));
  // The start's K_c zeta_n are the step's (start_cases_): only their weights change.
  const auto c = load_coefficients(state, alpha, acceleration);
  stiffening_start_.noalias() = start_cases_ * Eigen::Map<const Eigen::Matrix<double, kInertialLoadCases, 1>>(c.data());
  end_coefficients_ = stiffening_force(trial_, alpha, acceleration, stiffening_end_);
  residual_.tail(r) += 0.5 * h * (stiffening_start_ + stiffening_end_);
}

void FloatingFrameBody::stiffening_velocity_jacobian(const FloatingFrameState& state, double h, const Mat3& tangent) {
  // The term is h/2 sum_c (c_c,n K_c zeta_n + c_c,n+1 K_c zeta_{n+1}). The Euler and translation
  // cases' coefficients are the step's accelerations, alpha = (omega_{n+1} - omega_n) / h and
  // a = (v_{n+1} - v_n) / h + (omega_n + omega_{n+1}) x (v_n + v_{n+1}) / 4: they move with the
  // end velocities at O(1/h), so the term's derivative is O(1), as large as the stiffening
  // itself (a pendulum's angular acceleration stiffens it; left out, 16 stiffened modes
  // converged linearly at 0.7 per iteration and stopped at 50). The centrifugal cases move
  // with omega_{n+1} at the end, and so does gravity in the frame at the end, g_b = R^T g (the
  // translation cases' coefficients are a - g_b): dg_b = [g_b]x tangent domega.
  const Index r = inertia_.num_modes();
  const Vec3 w0 = state.velocity.segment<3>(3), w1 = trial_.velocity.segment<3>(3);
  const Vec3 v_sum = state.velocity.segment<3>(0) + trial_.velocity.segment<3>(0);
  const Mat3 by_v = Mat3::Identity() / h + 0.25 * cross_matrix(w0 + w1);  // da/dv_{n+1}
  const Mat3 by_omega = -0.25 * cross_matrix(v_sum);                       // da/domega_{n+1}
  const Mat3 gravity_turn = -cross_matrix(trial_.rotation.transpose() * gravity_) * tangent;  // d(-g_b)/domega
  stiffening_by_velocity_.setZero(r, 6);
  for (int k = 0; k < kInertialLoadCases; ++k) {
    const auto K = stiffening_cases_.middleCols(k * r, r);
    case_end_.noalias() = K * trial_.zeta;
    if (k < 6) {  // centrifugal: omega_a omega_b at the end
      const int a = kSymmetricPairs[k][0], b = kSymmetricPairs[k][1];
      stiffening_by_velocity_.col(3 + a) += (0.5 * h * w1[b]) * case_end_;
      stiffening_by_velocity_.col(3 + b) += (0.5 * h * w1[a]) * case_end_;
      continue;
    }
    if (k >= 9)  // gravity at the end alone: K_c zeta_{n+1}
      for (int j = 0; j < 3; ++j) stiffening_by_velocity_.col(3 + j) += (0.5 * h * gravity_turn(k - 9, j)) * case_end_;
    case_end_ += start_cases_.col(k);  // alpha and a: the same coefficient at both ends
    if (k < 9) {
      stiffening_by_velocity_.col(3 + (k - 6)) += 0.5 * case_end_;  // h/2 * (1/h)
    } else {
      const int i = k - 9;
      for (int j = 0; j < 3; ++j) {
        stiffening_by_velocity_.col(j) += (0.5 * h * by_v(i, j)) * case_end_;
        stiffening_by_velocity_.col(3 + j) += (0.5 * h * by_omega(i, j)) * case_end_;
      }
    }
  }
}

void FloatingFrameBody::trial_kinematics(const FloatingFrameState& state, double h) {
  const Index r = inertia_.num_modes();
  const Vec& w0 = state.velocity;
  const Vec& w1 = trial_.velocity;
  if (prescribed_ != nullptr) {
    trial_.rotation = prescribed_->rotation;
    trial_.position = prescribed_->position;
  } else {
    trial_.rotation = state.rotation * cayley_rotation(0.5 * h * (w0.segment<3>(3) + w1.segment<3>(3)));
    trial_.position =
        state.position + 0.5 * h * (state.rotation * w0.segment<3>(0) + trial_.rotation * w1.segment<3>(0));
  }
  trial_.zeta = state.zeta + 0.5 * h * (w0.tail(r) + w1.tail(r));
}

double FloatingFrameBody::evaluate_trial(const FloatingFrameState& state, double h, double start_scale) {
  // The end of the step from the trial velocities, its balances, and the residual of the
  // step's equations (projected on what a support leaves free), relative to their scale.
  const Index r = inertia_.num_modes();
  trial_kinematics(state, h);
  balance_at(trial_, end_);
  residual_.segment<3>(0) = end_.linear - start_.linear - 0.5 * h * (start_.force + end_.force);
  residual_.segment<3>(3) = end_.angular - start_.angular - 0.5 * h * (start_.torque + end_.torque);
  residual_.tail(r) = end_.modal_momentum - start_.modal_momentum - 0.5 * h * (start_.modal_load + end_.modal_load);
  add_stiffening(state, h);
  const double scale = start_scale + end_.linear.norm() + end_.angular.norm() + end_.modal_momentum.norm() +
                       h * (end_.force.norm() + end_.torque.norm() + end_.modal_load.norm()) + 1e-300;
  if (!reduced()) return residual_.norm() / scale;
  const Index f = frame_projection_.rows();
  reduced_residual_.resize(f + r);
  reduced_residual_.head(f).noalias() = frame_projection_ * residual_.head<6>();
  reduced_residual_.tail(r) = residual_.tail(r);
  return reduced_residual_.norm() / scale;
}

FloatingFrameStepStats FloatingFrameBody::step(FloatingFrameState& state, double h) {
  if (!(h > 0.0) || !std::isfinite(h)) throw InvalidInput("floating frame: the time step must be positive and finite");
  check(state);
  previous_omega_ = state.velocity.segment<3>(3);
  if (stiffening()) {  // K_c zeta_n, one column per load case: fixed over the step's iterations
    const Index r = inertia_.num_modes();
    start_cases_.resize(r, kInertialLoadCases);
    for (int k = 0; k < kInertialLoadCases; ++k)
      start_cases_.col(k).noalias() = stiffening_cases_.middleCols(k * r, r) * state.zeta;
  }
  if (support_ == FrameSupport::Free && prescribed_ == nullptr) return step_free(state, h);
  const Index r = inertia_.num_modes(), size = 6 + r;
  balance_at(state, start_);
  check_support(state);
  trial_ = state;
  // The iterations start from w_n: the first is then a linearly implicit step. (An explicit
  // predictor saves an iteration on a soft body but throws a stiff one's high modes far off.)
  constrain(state, trial_.velocity);
  // The residual is relative to the momenta and impulses of the step: those at its start, and
  // (iteration by iteration) those at its end, which alone are nonzero for a body at rest
  // that a prescribed motion starts to drive.
  const double start_scale = start_.linear.norm() + start_.angular.norm() + start_.modal_momentum.norm() +
                             h * (start_.force.norm() + start_.torque.norm() + start_.modal_load.norm());
  residual_.resize(size);
  if (reduced()) support_maps(state);
  start_velocity_ = trial_.velocity;
  FloatingFrameStepStats stats;
  schedule_.begin(h, prescribed_ != nullptr ? kDrivenStep : 1 + int(support_));
  for (stats.iterations = 1; stats.iterations <= kMaxIterations; ++stats.iterations) {
    stats.residual = evaluate_trial(state, h, start_scale);
    if (stats.residual <= kTolerance) {
      state = trial_;
      stats.fresh_rate = schedule_.fresh_rate();
      return stats;
    }
    // The Jacobian as jacobian_schedule.hpp says: kept from the last step for the first
    // correction, factored at the second iterate (unless keeping it is cheaper) and kept while
    // the iterations converge fast.
    const JacobianSchedule::Next next = schedule_.after_evaluation(stats.residual);
    if (next == JacobianSchedule::Next::Restart) {
      trial_.velocity = start_velocity_;
      continue;
    }
    if (!std::isfinite(stats.residual)) break;
    if (next == JacobianSchedule::Next::FactorAndSolve && !factor_jacobian(state, h)) break;
    if (!reduced()) {
      lu_.solve(residual_, correction_);
    } else {  // the balances the support's reactions do not enter, in the velocities it leaves free
      lu_.solve(reduced_residual_, reduced_correction_);
      const Index f = frame_velocities_.cols();
      correction_.resize(size);
      correction_.head<6>().noalias() = frame_velocities_ * reduced_correction_.head(f);
      correction_.tail(r) = reduced_correction_.tail(r);
    }
    trial_.velocity -= correction_;
    if (schedule_.converged_by_rate()) {
      trial_kinematics(state, h);
      state = trial_;
      stats.fresh_rate = schedule_.fresh_rate();
      return stats;
    }
  }
  schedule_.invalidate();
  // A stiffened body whose modes carry nearly all of its rotation about a support (many
  // Craig-Bampton modes held at a small face: the frame keeps 0.02 % of a link's inertia with
  // 16) can go unstable, the stiffening acting on the modes alone; a smaller step won't help.
  const std::string stiffened =
      stiffening() && prescribed_ == nullptr
          ? " With geometric stiffening and a basis of many modes held at a small face, the frame carries little of "
            "the body's rotational inertia and the step can become unstable: fewer modes, or no stiffening, help."
          : "";
  throw SolverFailure("floating frame: the implicit step did not converge (relative residual " +
                      std::to_string(stats.residual) +
                      "); the state was kept. A smaller time step helps where the motion is fast." + stiffened);
}

void FloatingFrameBody::loads_turn(double h, const Mat3& tangent) {
  // The loads' dependence on omega_{n+1} through R_{n+1} (dR = R [dtheta]x, dtheta = tangent
  // domega) and, for the moments, on eta_{n+1} through the points' motion u = X + Psi zeta. A
  // world-fixed force f at u: its moment (R u) x f moves by [f]x R [u]x dtheta and by -[f]x R
  // Psi dzeta, its modal load Psi^T R^T f by Psi^T [R^T f]x dtheta; gravity is such a force, m g
  // at the centre of mass (c = m u, Psi -> A). A body-fixed force f_b: the force R f_b moves by
  // -R [f_b]x dtheta, its moment about the origin p x R f_b + R (u x f_b) by that force's turn
  // and by -R [u x f_b]x dtheta (its dzeta part left out). Each enters the
  // residual as -h/2 (load at the end); a pendulum's gravity torque is what drives it, and
  // without these terms its step converged at 1/150 per iteration instead of 1e-4.
  const Index r = inertia_.num_modes();
  const Mat3& R1 = trial_.rotation;
  const auto world_force = [&](const Vec3& f, const Vec3& u, const auto& rows) {
    const Mat3 f_cross = cross_matrix(f);
    jacobian_.block<3, 3>(3, 3) -= (0.5 * h) * f_cross * R1 * cross_matrix(u) * tangent;
    jacobian_.block(3, 6, 3, r).noalias() += (0.25 * h * h) * (f_cross * R1) * rows;
    jacobian_.block(6, 3, r, 3).noalias() -=
        (0.5 * h) * rows.transpose() * (cross_matrix(R1.transpose() * f) * tangent);
  };
  if (gravity_.squaredNorm() > 0.0) {
    const double m = inertia_.mass();
    world_force(m * gravity_, inertia_.first_moment(trial_.zeta) / m, gravity_rows_);
  }
  for (Index i = 0; i < load_points_.cols(); ++i) {
    const auto rows = load_rows_.middleRows(3 * i, 3);
    const Vec3 u = load_points_.col(i) + rows * trial_.zeta;
    if (load_frame_ == LoadFrame::World) {
      world_force(load_forces_.col(i), u, rows);
    } else {
      const Vec3 f_b = load_forces_.col(i);
      const Mat3 turn_force = (0.5 * h) * R1 * cross_matrix(f_b) * tangent;
      jacobian_.block<3, 3>(0, 3) += turn_force;
      jacobian_.block<3, 3>(3, 3) += cross_matrix(trial_.position) * turn_force;  // p x F
      jacobian_.block<3, 3>(3, 3) += (0.5 * h) * R1 * cross_matrix(u.cross(f_b)) * tangent;
    }
  }
}

bool FloatingFrameBody::factor_jacobian(const FloatingFrameState& state, double h) {
  // The Jacobian by w_{n+1}, with zeta_{n+1} = zeta_n + h/2 (eta_n + eta_{n+1}): the momenta
  // M(zeta) w (their zeta-dependence included), turned to the world frame; dT/dzeta by w and
  // zeta; the modal stiffness and damping; the stiffening's dependence on the velocities
  // (stiffening_velocity_jacobian); the loads' turn with the frame (loads_turn).
  const Index r = inertia_.num_modes(), size = 6 + r;
  inertia_.mass_matrix(trial_.zeta, M_);
  inertia_.velocity_derivatives(trial_.zeta, trial_.velocity, dmomentum_, dgradient_dw_, dgradient_dzeta_);
  momentum_jacobian_ = M_;
  momentum_jacobian_.rightCols(r) += (0.5 * h) * dmomentum_;
  jacobian_.resize(size, size);
  const Mat3& R1 = trial_.rotation;
  jacobian_.topRows(3).noalias() = R1 * momentum_jacobian_.topRows(3);
  jacobian_.middleRows(3, 3).noalias() = R1 * momentum_jacobian_.middleRows(3, 3);
  jacobian_.middleRows(3, 3).noalias() += cross_matrix(trial_.position) * jacobian_.topRows(3);
  // The rotation's dependence on omega_{n+1}: R_{n+1} = R_n cay(a), a = h/2 (omega_n +
  // omega_{n+1}), turns by dR = R [dtheta]x with dtheta = T(a) da, T(a) = 4 / (4 + |a|^2)
  // (I - [a]x / 2) the Cayley map's tangent; and the position's on v_{n+1} (dp = h/2 R dv).
  const Vec3 a = 0.5 * h * (previous_omega_ + trial_.velocity.segment<3>(3));
  const Mat3 tangent = (0.5 * h * 4.0 / (4.0 + a.squaredNorm())) * (Mat3::Identity() - 0.5 * cross_matrix(a));
  const Mat3 turn_linear = -R1 * cross_matrix(pi_.segment<3>(0)) * tangent;
  jacobian_.block<3, 3>(0, 3) += turn_linear;
  jacobian_.block<3, 3>(3, 3) +=
      cross_matrix(trial_.position) * turn_linear - R1 * cross_matrix(pi_.segment<3>(3)) * tangent;
  // p_{n+1} = p_n + h/2 (R_n v_n + R_{n+1} v_{n+1}) moves with v_{n+1} and, through R_{n+1},
  // with omega_{n+1}; the angular balance about the world origin feels it through p x L and
  // the loads' moment p x F (a body far from the origin, falling fast, needs both).
  const Mat3 lever = -cross_matrix(end_.linear) + 0.5 * h * cross_matrix(end_.force);
  jacobian_.block<3, 3>(3, 0) += lever * (0.5 * h * R1);
  jacobian_.block<3, 3>(3, 3) -= lever * (0.5 * h * R1 * cross_matrix(trial_.velocity.segment<3>(0)) * tangent);
  jacobian_.bottomRows(r) = momentum_jacobian_.bottomRows(r);
  loads_turn(h, tangent);
  jacobian_.bottomRows(r) -= (0.5 * h) * dgradient_dw_;
  jacobian_.bottomRightCorner(r, r) -= (0.25 * h * h) * dgradient_dzeta_;
  jacobian_.bottomRightCorner(r, r) += (0.25 * h * h) * stiffness_ + (0.5 * h) * damping_;
  for (int k = 0; k < kInertialLoadCases && stiffening(); ++k)
    if (end_coefficients_[k] != 0.0)
      jacobian_.bottomRightCorner(r, r) +=
          (0.25 * h * h * end_coefficients_[k]) * stiffening_cases_.middleCols(k * r, r);
  if (stiffening()) {
    stiffening_velocity_jacobian(state, h, tangent);
    jacobian_.bottomLeftCorner(r, 6) += stiffening_by_velocity_;
  }
  if (!reduced()) return lu_.compute(jacobian_);
  // P J V by blocks, P = diag(frame_projection_, I) and V = diag(frame_velocities_, I).
  const Index f = frame_projection_.rows();
  projected_frame_rows_.noalias() = frame_projection_ * jacobian_.topRows<6>();  // f x (6 + r)
  reduced_jacobian_.resize(f + r, f + r);
  reduced_jacobian_.topLeftCorner(f, f).noalias() = projected_frame_rows_.leftCols<6>() * frame_velocities_;
  reduced_jacobian_.topRightCorner(f, r) = projected_frame_rows_.rightCols(r);
  reduced_jacobian_.bottomLeftCorner(r, f).noalias() = jacobian_.bottomLeftCorner(r, 6) * frame_velocities_;
  reduced_jacobian_.bottomRightCorner(r, r) = jacobian_.bottomRightCorner(r, r);
  return lu_.compute(reduced_jacobian_);
}

double FloatingFrameBody::energy(const FloatingFrameState& s) const {
  check(s);
  inertia_.mass_matrix(s.zeta, M_);
  const double kinetic = 0.5 * s.velocity.dot(M_ * s.velocity);
  const double elastic = 0.5 * s.zeta.dot(stiffness_ * s.zeta);
  const double potential = -gravity_.dot(inertia_.mass() * s.position + s.rotation * inertia_.first_moment(s.zeta));
  return kinetic + elastic + potential;
}

Vec3 FloatingFrameBody::linear_momentum(const FloatingFrameState& s) const {
  check(s);
  inertia_.mass_matrix(s.zeta, M_);
  return s.rotation * (M_.topRows(3) * s.velocity);
}

Vec3 FloatingFrameBody::angular_momentum(const FloatingFrameState& s) const {
  check(s);
  inertia_.mass_matrix(s.zeta, M_);
  const Vec3 linear = s.rotation * (M_.topRows(3) * s.velocity);
  return s.position.cross(linear) + s.rotation * (M_.middleRows(3, 3) * s.velocity);
}

}  // namespace corotate
