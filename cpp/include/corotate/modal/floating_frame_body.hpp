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
// stiffness and damping), which converge at a rate of order h |omega|; the Jacobian is kept
// while the iterations converge fast (a chord method) and refreshed when they slow down.
//
// Geometric stiffening (optional): the inertial loads of the frame's motion (centrifugal,
// Euler, translation and gravity) stress the body, and that stress stiffens it, which linear
// modes alone leave out (a spinning beam's modes then soften without bound past its first
// frequency). The modal load is then G - K_geo zeta with K_geo = sum_c c_c K_c over the twelve
// unit load cases of inertial_load_cases.hpp, c_c from each end's omega and gravity and the
// step's mean accelerations (so the scheme stays symmetric).
#pragma once

#include <vector>

#include "corotate/materials/determinant_derivatives.hpp"  // cross_matrix
#include "corotate/modal/floating_frame_inertia.hpp"
#include "corotate/modal/inertial_load_cases.hpp"
#include "corotate/modal/jacobian_schedule.hpp"
#include "corotate/solvers/small_dense_lu.hpp"

namespace corotate {

// The Cayley map: a rotation close to exp([a]x), exactly orthogonal.
inline Mat3 cayley_rotation(const Vec3& a) {
  const Mat3 A = cross_matrix(a);
  return Mat3::Identity() + (4.0 / (4.0 + a.squaredNorm())) * (A + 0.5 * A * A);
}

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

// The direction of nodal forces: fixed in the world, or turning with the frame (a follower load).
enum class LoadFrame { World, Body };

struct FloatingFrameStepStats {
  int iterations = 0;
  double residual = 0.0;  // relative, of the last iteration
  // The residual's reduction one correction after a Jacobian factored in the step (0: none
  // was; jacobian_schedule.hpp): small as the residual itself where the Jacobian is right.
  double fresh_rate = 0.0;
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
  // Forces on nodes: points (3 x m) their rest positions in the frame, rows (3m x r) their rows
  // of the basis, forces (3 x m) in `frame`. Replaces the loads set before (m = 0: none).
  void set_node_loads(Nodes points, Eigen::MatrixXd rows, Nodes forces, LoadFrame frame);
  // The modal geometric stiffness of each unit inertial load case (12 matrices r x r, in the
  // order of inertial_load_cases.hpp); an empty list switches the stiffening off.
  void set_geometric_stiffness(const std::vector<Eigen::MatrixXd>& per_case);
  bool stiffening() const { return stiffening_cases_.size() > 0; }
  // A state at rest at the frame's identity pose with zeta = 0.
  FloatingFrameState rest_state() const;
  // One step of h; throws InvalidInput for a bad state or step, SolverFailure when the
  // iterations do not converge (the state is then left as it was).
  FloatingFrameStepStats step(FloatingFrameState& state, double h);
  // n steps (free or held by the support); when one fails, the state is put back as it was
  // before the call and the error rethrown. Returns the iterations of all n steps and the
  // last step's residual.
  FloatingFrameStepStats advance(FloatingFrameState& state, double h, int n);

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
  // Gravity and the nodal loads in the frame: force, moment about the origin, modal load.
  void frame_loads(const FloatingFrameState& s, Vec3& force, Vec3& torque, Eigen::Ref<Vec> modal) const;
  // A free body's step, about its centre of mass (floating_frame_free_step.cpp).
  FloatingFrameStepStats step_free(FloatingFrameState& state, double h);
  // w_rel = (c/m x omega - A eta / m, omega, eta): the frame velocity that keeps the centre of mass still.
  void relative_velocity(const Vec& zeta, const Vec3& omega, const Eigen::Ref<const Vec>& eta, Vec& w_rel) const;
  // A free body's momenta and loads: linear (m V), angular and moments about its centre of
  // mass, modal.
  void centre_balance_at(const Vec& zeta, const Mat3& R, const Vec3& V, const Vec& w_rel, Balance& b) const;
  // (The stiffening's dependence on the velocities is left out here: a free body's frame
  // velocities enter it through w_rel, and its inertial loads are small beside a driven one's.)
  bool factor_free_jacobian(double h, const Vec3& V0);  // false: singular
  // + h/2 (K_geo zeta)_{n, n+1} in the modal residual, from state and trial_'s frame velocities.
  void add_stiffening(const FloatingFrameState& state, double h);
  // stiffening_by_velocity_ = d/d(v, omega)_{n+1} of that term (r x 6, the frame's velocities
  // in the frame).
  void stiffening_velocity_jacobian(const FloatingFrameState& state, double h, const Mat3& tangent);
  // The loads' turn with the frame into jacobian_ (tangent: dtheta / domega_{n+1}).
  void loads_turn(double h, const Mat3& tangent);
  // trial_'s end of the step (rotation, position, zeta) from trial_.velocity.
  void trial_kinematics(const FloatingFrameState& state, double h);
  // trial_'s end of the step and residual_ from trial_.velocity; returns the relative residual.
  double evaluate_trial(const FloatingFrameState& state, double h, double start_scale);
  // The Jacobian's leading part at trial_ (M_, pi_, end_ from its balance), factored into lu_;
  // false when it is singular.
  bool factor_jacobian(const FloatingFrameState& state, double h);
  // The twelve load cases' coefficients at s for the step's accelerations (gravity in s's frame).
  std::array<double, kInertialLoadCases> load_coefficients(const FloatingFrameState& s, const Vec3& alpha,
                                                           const Vec3& acceleration) const;
  // out = K_geo zeta at s for the step's accelerations; returns the load cases' coefficients.
  std::array<double, kInertialLoadCases> stiffening_force(const FloatingFrameState& s, const Vec3& alpha,
                                                          const Vec3& acceleration, Vec& out);
  void check(const FloatingFrameState& s) const;
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
  Nodes load_points_, load_forces_;
  Eigen::MatrixXd load_rows_;
  LoadFrame load_frame_ = LoadFrame::World;
  Eigen::MatrixXd stiffening_cases_;  // r x 12 r: [K_0 ... K_11]
  std::array<double, kInertialLoadCases> end_coefficients_{};
  Vec stiffening_start_, stiffening_end_;
  Eigen::MatrixXd stiffening_by_velocity_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> gravity_rows_;  // A / m: the centre of mass's basis rows
  Vec case_end_;                 // K_c zeta_{n+1}, one load case c
  Eigen::MatrixXd start_cases_;  // r x 12: K_c zeta_n, the step's start, per load case
  Eigen::MatrixXd frame_velocities_, frame_projection_, projected_frame_rows_, reduced_jacobian_;
  Vec reduced_residual_, reduced_correction_;
  // Work space (sized on first use).
  mutable Eigen::MatrixXd M_;
  mutable Vec pi_;
  Eigen::MatrixXd jacobian_, momentum_jacobian_, dmomentum_, dgradient_dw_, dgradient_dzeta_;
  Eigen::MatrixXd relative_map_, gradient_jacobian_;  // the free step's
  Vec unknown_, w_rel_, w_rel_start_;
  SmallDenseLU lu_;
  JacobianSchedule schedule_{kTolerance};                       // when lu_ is factored (kept across steps)
  static constexpr int kFreeStep = 0, kDrivenStep = 4;  // schedule_'s kinds; held: 1 + FrameSupport
  Vec start_unknown_, start_velocity_;              // a step's start guesses, for a restart
  Vec residual_, correction_;
  Balance start_, end_;
  FloatingFrameState trial_;
  Vec3 previous_omega_ = Vec3::Zero();  // omega_n of the step being solved
};

}  // namespace corotate
