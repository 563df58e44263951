// The step of a free floating-frame body, written about its centre of mass.
//
// The frame's origin is where the basis is held (a root face), generally far from the centre
// of mass, so its velocity v carries the body's whole translation. The equations in (v, omega,
// eta) are exact, but their trapezoidal discretisation is not Galilean invariant: the modal
// equation's terms A^T v and -v . (A_k x omega) cancel only to O(h^2 |omega|^2 |v|), and a
// body thrown at 3 m/s gains energy until the step fails. About the centre of mass the
// translation separates exactly, T = 1/2 m |V|^2 + T_rel(zeta, omega, eta), for any mode
// shapes; so here the unknowns are (V, omega, eta), V the centre of mass's world velocity:
//
//   m V_{n+1} - m V_n = h (F_n + F_{n+1}) / 2,   x_c,{n+1} = x_c,n + h (V_n + V_{n+1}) / 2,
//   H = x_c x m V + R pi_omega^c balanced with the moments about the world origin (less
//   x_c,n x the linear balance: the same solution, without large cancelling terms),
//   pi_eta^c balanced with dT_rel/dzeta, the modal loads, - K zeta - D eta,
//
// where pi^c = M(zeta) w_rel, w_rel = (v_c, omega, eta) with v_c = c/m x omega - A eta / m the
// frame velocity that keeps the centre of mass still (then pi_v = 0, and dT_rel/dzeta is
// dT/dzeta at w_rel). Gravity, uniform, then acts on V alone. The state keeps the frame's
// origin and velocity: p = x_c - R c/m, v = R^T V + v_c.
#include <string>

#include "corotate/materials/determinant_derivatives.hpp"  // cross_matrix
#include "corotate/modal/floating_frame_body.hpp"

namespace corotate {

void FloatingFrameBody::relative_velocity(const Vec& zeta, const Vec3& omega, const Eigen::Ref<const Vec>& eta,
                                          Vec& w_rel) const {
  const Index r = inertia_.num_modes();
  const double m = inertia_.mass();
  w_rel.resize(6 + r);
  Vec3 modal_shift = Vec3::Zero();  // A eta
  for (Index k = 0; k < r; ++k) modal_shift += eta[k] * inertia_.modal_first_moment(k);
  w_rel.segment<3>(0) = (inertia_.first_moment(zeta) / m).cross(omega) - modal_shift / m;
  w_rel.segment<3>(3) = omega;
  w_rel.tail(r) = eta;
}

void FloatingFrameBody::centre_balance_at(const Vec& zeta, const Mat3& R, const Vec3& V, const Vec& w_rel,
                                          Balance& b) const {
  const Index r = inertia_.num_modes();
  const double m = inertia_.mass();
  inertia_.momenta(zeta, w_rel, pi_);  // pi_v = 0 by the choice of w_rel
  b.linear = m * V;
  b.angular = R * pi_.segment<3>(3);  // about the centre of mass
  b.modal_momentum = pi_.tail(r);
  inertia_.kinetic_energy_gradient(zeta, w_rel, b.modal_load);
  // Loads: gravity acts on the centre of mass alone; a nodal force f (frame components f_b)
  // also turns the body about its centre, (u - c/m) x f_b, and loads mode k by (Psi_k - A_k
  // / m) . f_b.
  Vec3 force = R.transpose() * (m * gravity_), torque = Vec3::Zero();
  const Vec3 centre_in_frame = inertia_.first_moment(zeta) / m;
  for (Index i = 0; i < load_points_.cols(); ++i) {
    const auto rows = load_rows_.middleRows(3 * i, 3);
    const Vec3 f =
        load_frame_ == LoadFrame::Body ? Vec3(load_forces_.col(i)) : Vec3(R.transpose() * load_forces_.col(i));
    force += f;
    torque += (load_points_.col(i) + rows * zeta - centre_in_frame).cross(f);
    b.modal_load.noalias() += rows.transpose() * f;
    for (Index k = 0; k < r; ++k) b.modal_load[k] -= inertia_.modal_first_moment(k).dot(f) / m;
  }
  b.force = R * force;
  b.torque = R * torque;  // about the centre of mass
  b.modal_load.noalias() -= stiffness_ * zeta;
  b.modal_load.noalias() -= damping_ * w_rel.tail(r);
}

FloatingFrameStepStats FloatingFrameBody::step_free(FloatingFrameState& state, double h) {
  const Index r = inertia_.num_modes(), size = 6 + r;
  const double m = inertia_.mass();
  const Vec3 omega0 = state.velocity.segment<3>(3);
  relative_velocity(state.zeta, omega0, state.velocity.tail(r), w_rel_start_);
  const Mat3& R0 = state.rotation;
  const Vec3 centre0 = state.position + R0 * inertia_.first_moment(state.zeta) / m;
  const Vec3 V0 = R0 * (state.velocity.segment<3>(0) - w_rel_start_.segment<3>(0));
  centre_balance_at(state.zeta, R0, V0, w_rel_start_, start_);
  const double start_scale = start_.linear.norm() + start_.angular.norm() + start_.modal_momentum.norm() +
                             h * (start_.force.norm() + start_.torque.norm() + start_.modal_load.norm());
  unknown_.resize(size);
  unknown_ << V0, omega0, state.velocity.tail(r);
  start_unknown_ = unknown_;
  residual_.resize(size);
  trial_ = state;
  // The end of the step from unknown_: its kinematics and the frame velocity w_rel_.
  const auto end_kinematics = [&] {
    const Vec3 V1 = unknown_.segment<3>(0), omega1 = unknown_.segment<3>(3);
    trial_.zeta = state.zeta + 0.5 * h * (state.velocity.tail(r) + unknown_.tail(r));
    trial_.rotation = R0 * cayley_rotation(0.5 * h * (omega0 + omega1));
    relative_velocity(trial_.zeta, omega1, unknown_.tail(r), w_rel_);
    trial_.position = centre0 + 0.5 * h * (V0 + V1) - trial_.rotation * inertia_.first_moment(trial_.zeta) / m;
    trial_.velocity = w_rel_;
    trial_.velocity.segment<3>(0) += trial_.rotation.transpose() * V1;
  };
  FloatingFrameStepStats stats;
  schedule_.begin(h, kFreeStep);
  for (stats.iterations = 1; stats.iterations <= kMaxIterations; ++stats.iterations) {
    const Vec3 V1 = unknown_.segment<3>(0);
    end_kinematics();
    centre_balance_at(trial_.zeta, trial_.rotation, V1, w_rel_, end_);
    residual_.segment<3>(0) = end_.linear - start_.linear - 0.5 * h * (start_.force + end_.force);
    // The angular balance about the world origin, H = x_c x m V + R pi^c, less x_c,n x the
    // linear one (the same solution, without the large, cancelling x_c x L of a body far from
    // the origin): what is left of x_c x L and of the forces' moments is the centre's motion
    // over the step, x_c,{n+1} - x_c,n = h/2 (V_n + V_{n+1}).
    residual_.segment<3>(3) = end_.angular - start_.angular + (0.5 * h * m) * V0.cross(V1) -
                              0.5 * h * (start_.torque + end_.torque) - (0.25 * h * h) * (V0 + V1).cross(end_.force);
    residual_.tail(r) = end_.modal_momentum - start_.modal_momentum - 0.5 * h * (start_.modal_load + end_.modal_load);
    add_stiffening(state, h);
    const double scale = start_scale + end_.linear.norm() + end_.angular.norm() + end_.modal_momentum.norm() +
                         h * (end_.force.norm() + end_.torque.norm() + end_.modal_load.norm()) + 1e-300;
    stats.residual = residual_.norm() / scale;
    if (stats.residual <= kTolerance) {
      state = trial_;
      stats.fresh_rate = schedule_.fresh_rate();
      return stats;
    }
    const JacobianSchedule::Next next = schedule_.after_evaluation(stats.residual);
    if (next == JacobianSchedule::Next::Restart) {
      unknown_ = start_unknown_;
      continue;
    }
    if (!std::isfinite(stats.residual)) break;
    if (next == JacobianSchedule::Next::FactorAndSolve && !factor_free_jacobian(h, V0)) break;
    lu_.solve(residual_, correction_);
    unknown_ -= correction_;
    if (schedule_.converged_by_rate()) {
      end_kinematics();
      state = trial_;
      stats.fresh_rate = schedule_.fresh_rate();
      return stats;
    }
  }
  schedule_.invalidate();
  throw SolverFailure("floating frame: the implicit step did not converge (relative residual " +
                      std::to_string(stats.residual) + "); the state was kept. A smaller time step helps.");
}

bool FloatingFrameBody::factor_free_jacobian(double h, const Vec3& V0) {
  // The Jacobian by (V, omega, eta)_{n+1}: the momenta and dT/dzeta at w_rel, whose
  // dependence on (omega, eta) is d w_rel = E d(omega, eta) (v_c = c/m x omega - A eta / m,
  // c moving with zeta = ... + h/2 eta), and on zeta directly; the translation's own rows.
  const Index r = inertia_.num_modes(), size = 6 + r;
  const double m = inertia_.mass();
  const Vec3 omega = unknown_.segment<3>(3);
  inertia_.mass_matrix(trial_.zeta, M_);
  inertia_.velocity_derivatives(trial_.zeta, w_rel_, dmomentum_, dgradient_dw_, dgradient_dzeta_);
  relative_map_.setZero(size, 3 + r);
  relative_map_.block<3, 3>(0, 0) = cross_matrix(inertia_.first_moment(trial_.zeta) / m);
  for (Index k = 0; k < r; ++k)
    relative_map_.block<3, 1>(0, 3 + k) =
        (0.5 * h / m) * inertia_.modal_first_moment(k).cross(omega) - inertia_.modal_first_moment(k) / m;
  relative_map_.bottomRows(3 + r).setIdentity();
  // d pi / d(omega, eta) and d(dT/dzeta) / d(omega, eta), with the direct zeta-dependence. The
  // map is the identity below its first three rows: X E = X.rightCols + X.leftCols(3) E.topRows(3)
  // (an eighth of the full product's work).
  momentum_jacobian_ = M_.rightCols(3 + r);
  momentum_jacobian_.noalias() += M_.leftCols<3>() * relative_map_.topRows<3>();
  momentum_jacobian_.rightCols(r) += (0.5 * h) * dmomentum_;
  gradient_jacobian_ = dgradient_dw_.rightCols(3 + r);
  gradient_jacobian_.noalias() += dgradient_dw_.leftCols<3>() * relative_map_.topRows<3>();
  gradient_jacobian_.rightCols(r) += (0.5 * h) * dgradient_dzeta_;
  const Mat3& R1 = trial_.rotation;
  const Vec3 a = 0.5 * h * (previous_omega_ + omega);
  const Mat3 tangent = (0.5 * h * 4.0 / (4.0 + a.squaredNorm())) * (Mat3::Identity() - 0.5 * cross_matrix(a));
  jacobian_.setZero(size, size);
  jacobian_.block<3, 3>(0, 0) = m * Mat3::Identity();
  jacobian_.block<3, 3>(3, 0) = (0.5 * h * m) * cross_matrix(V0) + (0.25 * h * h) * cross_matrix(end_.force);
  jacobian_.block(3, 3, 3, 3 + r).noalias() = R1 * momentum_jacobian_.middleRows(3, 3);
  jacobian_.block<3, 3>(3, 3) -= R1 * cross_matrix(pi_.segment<3>(3)) * tangent;
  jacobian_.bottomRightCorner(r, 3 + r) = momentum_jacobian_.bottomRows(r) - (0.5 * h) * gradient_jacobian_;
  jacobian_.bottomRightCorner(r, r) += (0.25 * h * h) * stiffness_ + (0.5 * h) * damping_;
  for (int k = 0; k < kInertialLoadCases && stiffening(); ++k)
    if (end_coefficients_[k] != 0.0)
      jacobian_.bottomRightCorner(r, r) +=
          (0.25 * h * h * end_coefficients_[k]) * stiffening_cases_.middleCols(k * r, r);
  return lu_.compute(jacobian_);
}

}  // namespace corotate
