// Rigid obstacles a body touches: a ground plane and analytic shapes, static or moved by
// the user between frames (a probe held by a haptic device).
//
// Each shape is a signed distance function in its own frame (negative inside, with the
// outward unit normal as its gradient); the pose places it in the world. Every distance here
// is exact (a true Euclidean distance outside), so a node's path can be marched against it
// (contact/contact_set.hpp): the distance bounds how far the path can go without touching.
//
// The pose is guarded by a mutex: a haptic thread may move a tool while another thread steps
// the body; a step reads one consistent pose at its start (snapshot()).
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "corotate/common.hpp"

namespace corotate {

// A rigid placement x_world = rotation * x_local + translation.
struct Pose {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  Vec3 to_world(const Vec3& local) const { return rotation * local + translation; }
  Vec3 to_local(const Vec3& world) const { return rotation.transpose() * (world - translation); }
  // Throws InvalidInput unless finite with a proper rotation (orthonormal, det +1, to 1e-9).
  void validate() const;
};

class Obstacle {
 public:
  virtual ~Obstacle() = default;
  // Signed distance of a point in the shape's own frame; writes the outward unit normal.
  virtual double local_distance(const Vec3& p, Vec3& normal) const = 0;
  // A shape whose surface moves by more than its pose (a triangle mesh whose vertices are
  // moved: another body's surface) reports the velocity of its surface point nearest to p,
  // in its own frame; rigid shapes move only with their pose.
  virtual bool deforms() const { return false; }
  virtual Vec3 local_velocity(const Vec3& /*p*/) const { return Vec3::Zero(); }
  // "sphere of radius 0.1" and the like, for messages.
  virtual std::string describe() const = 0;

  Pose pose() const;
  void set_pose(const Pose& pose);  // validated; throws InvalidInput, pose unchanged
  // Incremented by every set_pose, so a simulation can tell the obstacle moved.
  long long version() const;

 private:
  mutable std::mutex mutex_;
  Pose pose_;
  long long version_ = 0;
};

// The half-space z <= 0 of its frame is solid (a ground plane: its normal is the frame's z).
class HalfSpace final : public Obstacle {
 public:
  double local_distance(const Vec3& p, Vec3& normal) const override;
  std::string describe() const override { return "plane"; }
};

class Sphere final : public Obstacle {
 public:
  explicit Sphere(double radius);
  double local_distance(const Vec3& p, Vec3& normal) const override;
  std::string describe() const override;
  double radius() const { return radius_; }

 private:
  double radius_;
};

// Axis-aligned in its frame: |x_i| <= half_extents_i.
class Box final : public Obstacle {
 public:
  explicit Box(const Vec3& half_extents);
  double local_distance(const Vec3& p, Vec3& normal) const override;
  std::string describe() const override;

 private:
  Vec3 half_;
};

// Points within radius of the segment from (0, 0, -half_length) to (0, 0, half_length).
class Capsule final : public Obstacle {
 public:
  Capsule(double radius, double half_length);
  double local_distance(const Vec3& p, Vec3& normal) const override;
  std::string describe() const override;

 private:
  double radius_, half_length_;
};

// A solid cylinder about the frame's z axis: x^2 + y^2 <= radius^2, |z| <= half_length.
class Cylinder final : public Obstacle {
 public:
  Cylinder(double radius, double half_length);
  double local_distance(const Vec3& p, Vec3& normal) const override;
  std::string describe() const override;

 private:
  double radius_, half_length_;
};

}  // namespace corotate
