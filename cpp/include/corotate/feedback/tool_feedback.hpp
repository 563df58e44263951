// Force feedback through contact: the force a body exerts on a rigid tool (an obstacle the
// hand moves) and its stiffness, for a haptic loop at about 1 kHz between two body steps at
// 100 Hz.
//
// After each body step, update() takes the force the body's contacts exerted on the tool at
// the step's end, F0 (the negative of the contact forces on the body: normal and friction),
// and the tool's position p0 there. Between steps, the haptic loop asks for the force at the
// device's position p: F(p) = F0 + K (p - p0), with K = dF/dp the body's stiffness as the
// tool feels it. K is the secant of the force along the tool's own motion, updated at every
// body step by the symmetric rank-one-pair correction of Powell (PSB): with s = p0 - p_prev
// and y = F0 - F_prev,
//     r = y - K s,  K <- K + (r s^T + s r^T) / s^T s - (r^T s) s s^T / (s^T s)^2,
// the symmetric matrix nearest to K (Frobenius) with K s = y. A tool pressing into the body
// keeps moving along the same direction, where this secant is the paper's averaged
// (secant) stiffness of the whole body under the tool, large deformation and the contact's
// growing area included; the directions the tool has not moved along keep the last value.
// When the tool leaves the body (no contact), F and K are zero.
//
// update() is called by the thread that steps the body, query() by the haptic thread: one
// mutex guards the few numbers they share; query() allocates nothing.
#pragma once

#include <memory>
#include <mutex>

#include "corotate/contact/obstacle.hpp"
#include "corotate/simulation.hpp"

namespace corotate {

class ToolFeedback {
 public:
  // tool: an obstacle of the simulation (checked at each update).
  explicit ToolFeedback(std::shared_ptr<Obstacle> tool);

  // After a body step of sim (throws InvalidInput when the tool is not one of its obstacles).
  void update(const Simulation& sim);
  struct Feedback {
    Vec3 force = Vec3::Zero();      // on the tool [N]
    Mat3 stiffness = Mat3::Zero();  // dF/dp [N/m]
  };
  // The force on the tool at position p (its pose's translation), and dF/dp.
  Feedback query(const Vec3& position) const;
  // What update() found: force and position at the last step, and whether it touches.
  Vec3 force() const;
  Vec3 position() const;
  bool touching() const;

 private:
  std::shared_ptr<Obstacle> tool_;
  mutable std::mutex mutex_;
  Vec3 force_ = Vec3::Zero(), position_ = Vec3::Zero();
  Mat3 stiffness_ = Mat3::Zero();
  bool touching_ = false, seen_ = false;
};

}  // namespace corotate
