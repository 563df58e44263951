#include "corotate/feedback/tool_feedback.hpp"

namespace corotate {

ToolFeedback::ToolFeedback(std::shared_ptr<Obstacle> tool) : tool_(std::move(tool)) {
  if (!tool_) throw InvalidInput("ToolFeedback needs a tool (an obstacle)");
}

void ToolFeedback::update(const Simulation& sim) {
  int index = -1;
  for (size_t j = 0; j < sim.obstacles().size(); ++j)
    if (sim.obstacles()[j].obstacle == tool_) index = static_cast<int>(j);
  if (index < 0) throw InvalidInput("the tool (" + tool_->describe() + ") is not an obstacle of this simulation");
  const ContactSet& set = sim.contacts();
  Vec3 force = Vec3::Zero();
  bool touching = false;
  if (set.forces().cols() == static_cast<Index>(set.contacts().size()))
    for (size_t k = 0; k < set.contacts().size(); ++k)
      if (set.contacts()[k].obstacle == index) {
        force -= set.forces().col(static_cast<Index>(k));  // the body pushes back on the tool
        touching = true;
      }
  const Vec3 position = tool_->pose().translation;

  const std::lock_guard<std::mutex> lock(mutex_);
  if (!touching) {
    stiffness_.setZero();
  } else if (seen_ && touching_) {  // a secant only between two states in contact (a first touch jumps)
    const Vec3 s = position - position_, y = force - force_;
    const double ss = s.squaredNorm();
    if (ss > 0) {  // PSB: the nearest symmetric K with K s = y (see the header)
      const Vec3 r = y - stiffness_ * s;
      stiffness_ += (r * s.transpose() + s * r.transpose()) / ss - (r.dot(s) / (ss * ss)) * s * s.transpose();
    }
  }
  force_ = force;
  position_ = position;
  touching_ = touching;
  seen_ = true;
}

ToolFeedback::Feedback ToolFeedback::query(const Vec3& position) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  Feedback f;
  if (!touching_) return f;
  f.stiffness = stiffness_;
  f.force = force_ + stiffness_ * (position - position_);
  return f;
}

Vec3 ToolFeedback::force() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return force_;
}

Vec3 ToolFeedback::position() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return position_;
}

bool ToolFeedback::touching() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return touching_;
}

}  // namespace corotate
