// A modal body on a floating frame (floating_frame_inertia.hpp), free or under gravity, with
// its modal stiffness and damping, stepped by an implicit, symmetric scheme that balances
// the world-frame momenta exactly:
//
//   L_{n+1} - L_n = h (F_n + F_{n+1}) / 2          L = R pi_v             (linear momentum)
//   H_{n+1} - H_n = h (T_n + T_{n+1}) / 2          H = p x L + R pi_w     (angular, about the world origin)
//   pi_eta,{n+1} - pi_eta,n = h (G_n + G_{n+1}) / 2   G = dT/dzeta + Q - K zeta - D eta
//
// with the kinematics R_{n+1} = R_n cay(h (omega_n + omega_{n+1}) / 2) (the Cayley map keeps R
// a rotation), p_{n+1} = p_n + h (R_n v_n + R_{n+1} v_{n+1}) / 2, zeta_{n+1} = zeta_n +
// h (eta_n + eta_{n+1}) / 2. A free body's momenta are then kept to the solver's tolerance
// (round-off), whatever the step; the scheme is time-reversible, so its energy error stays
// bounded instead of drifting. The unknowns w_{n+1} are found by Newton iterations with the
// leading part of the Jacobian (the mass matrix turned to the world frame, and the modal
// stiffness and damping), which converge at a rate of order h |omega|.
#pragma once

#include <Eigen/LU>

#include "corotate/modal/floating_frame_inertia.hpp"

namespace corotate {

struct FloatingFrameState {
  Vec3 position = Vec3::Zero();     // p, the frame's origin in the world
  Mat3 rotation = Mat3::Identity();  // R, frame to world
  Vec zeta;                          // modal coordinates (r)
  Vec velocity;                      // w = (v, omega, eta) in the frame (6 + r)
};

// What holds the frame: nothing, a spherical joint at its origin, or a revolute joint through
// its origin about an axis fixed in the frame (and in the world). The origin then stays put
// and the balances the joint's reactions enter are left out of the step.
enum class FrameSupport { Free, Spherical, Revolute };

// A pose of the frame with its velocities (v and omega in the frame), for prescribed motion.
struct FramePose {
  Vec3 position = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();
  Vec3 velocity = Vec3::Zero(), angular_velocity = Vec3::Zero();
};

struct FloatingFrameStepStats {
  int iterations = 0;
  double residual = 0.0;  // relative, of the last iteration
};

class FloatingFrameBody {
 public:
  // K, D: modal stiffness and damping (r x r, symmetric; D may be empty for none).
  FloatingFrameBody(FloatingFrameInertia inertia, Eigen::MatrixXd stiffness, Eigen::MatrixXd damping = {});
  const FloatingFrameInertia& inertia() const { return inertia_; }
  void set_gravity(const Vec3& g) { gravity_ = g; }
  // axis: for Revolute, in the frame (normalised here). The state stepped must then have a
  // zero origin velocity (and, revolute, its angular velocity along the axis).
  void set_support(FrameSupport support, const Vec3& axis = Vec3::UnitZ());
  // A state at rest at the frame's identity pose with zeta = 0.
  FloatingFrameState rest_state() const;
  // One step of h; throws InvalidInput for a bad state or step, SolverFailure when the
  // iterations do not converge (the state is then left as it was).
  FloatingFrameStepStats step(FloatingFrameState& state, double h);

  // One step with the frame's motion prescribed: `end` is its pose and velocities at the end
  // of the step (the state holds those at its start); only the modes are solved for. A hub
  // driven at a given angular velocity, as in the spin-up beam.
  FloatingFrameStepStats step_prescribed(FloatingFrameState& state, double h, const FramePose& end);

  // Kinetic + elastic + gravitational energy; world momenta (angular about the origin).
  double energy(const FloatingFrameState& s) const;
  Vec3 linear_momentum(const FloatingFrameState& s) const;
  Vec3 angular_momentum(const FloatingFrameState& s) const;

  static constexpr int kMaxIterations = 50;
  static constexpr double kTolerance = 1e-14;

 private:
  struct Balance {  // the momenta and the loads at one end of the step
    Vec3 linear, angular, force, torque;  // world frame; angular and torque about the origin
    Vec modal_momentum, modal_load;
  };
  void balance_at(const FloatingFrameState& s, Balance& b) const;
  void check(const FloatingFrameState& s) const;
  void predict(const FloatingFrameState& s, double h, Vec& w);
  void check_support(const FloatingFrameState& s) const;
  void constrain(const FloatingFrameState& s, Vec& w) const;
  void support_maps(const FloatingFrameState& s);
  bool reduced() const { return prescribed_ != nullptr || support_ != FrameSupport::Free; }

  FloatingFrameInertia inertia_;
  Eigen::MatrixXd stiffness_, damping_;
  Vec3 gravity_ = Vec3::Zero();
  FrameSupport support_ = FrameSupport::Free;
  Vec3 axis_ = Vec3::UnitZ();
  const FramePose* prescribed_ = nullptr;  // during step_prescribed
  Eigen::MatrixXd free_velocities_, projection_, projected_jacobian_, reduced_jacobian_;
  Vec reduced_residual_, reduced_correction_;
  // Work space (sized on first use).
  mutable Eigen::MatrixXd M_;
  mutable Vec pi_, gradient_, force_;
  Eigen::MatrixXd jacobian_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Vec residual_, correction_;
  Balance start_, end_;
  FloatingFrameState trial_;
};

}  // namespace corotate
