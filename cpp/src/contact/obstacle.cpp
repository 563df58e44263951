#include "corotate/contact/obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace corotate {

namespace {

double sign(double v) { return v < 0 ? -1.0 : 1.0; }  // +1 at 0: any side of a tie will do

// A unit vector along (x, y, 0), or +x on the axis, where every direction is as near.
Vec3 radial_direction(const Vec3& p) {
  const double r = std::hypot(p.x(), p.y());
  return r > 0 ? Vec3(p.x() / r, p.y() / r, 0) : Vec3::UnitX();
}

void check_length(double value, const char* name, bool zero_allowed) {
  if (!std::isfinite(value) || value < 0 || (!zero_allowed && value == 0)) {
    std::ostringstream msg;
    msg << name << " must be " << (zero_allowed ? "non-negative" : "positive") << " and finite, not " << value;
    throw InvalidInput(msg.str());
  }
}

}  // namespace

void Pose::validate() const {
  if (!rotation.allFinite() || !translation.allFinite()) throw InvalidInput("an obstacle's pose must be finite");
  const double off = (rotation.transpose() * rotation - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (off > 1e-9 || rotation.determinant() < 0) {
    std::ostringstream msg;
    msg << "an obstacle's rotation must be a proper rotation matrix (R^T R = I to 1e-9, det R = +1); this one is off "
           "by "
        << off << " with det " << rotation.determinant();
    throw InvalidInput(msg.str());
  }
}

Pose Obstacle::pose() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return pose_;
}

void Obstacle::set_pose(const Pose& pose) {
  pose.validate();
  const std::lock_guard<std::mutex> lock(mutex_);
  pose_ = pose;
  ++version_;
}

long long Obstacle::version() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

double HalfSpace::local_distance(const Vec3& p, Vec3& normal) const {
  normal = Vec3::UnitZ();
  return p.z();
}

Sphere::Sphere(double radius) : radius_(radius) { check_length(radius, "a sphere's radius", false); }

double Sphere::local_distance(const Vec3& p, Vec3& normal) const {
  const double r = p.norm();
  normal = r > 0 ? Vec3(p / r) : Vec3::UnitZ();
  return r - radius_;
}

std::string Sphere::describe() const { return "sphere of radius " + std::to_string(radius_); }

Box::Box(const Vec3& half_extents) : half_(half_extents) {
  for (int i = 0; i < 3; ++i) check_length(half_extents[i], "a box's half extents", false);
}

double Box::local_distance(const Vec3& p, Vec3& normal) const {
  const Vec3 q = p.cwiseAbs() - half_;  // per axis: how far outside that pair of faces
  const Vec3 outside = q.cwiseMax(0.0);
  const double d = outside.norm();
  if (d > 0) {  // nearest is a face, edge or corner point
    for (int i = 0; i < 3; ++i) normal[i] = sign(p[i]) * outside[i] / d;
    return d;
  }
  int axis = 0;  // inside: the nearest face
  q.maxCoeff(&axis);
  normal = sign(p[axis]) * Vec3::Unit(axis);
  return q[axis];
}

std::string Box::describe() const {
  std::ostringstream s;
  s << "box of half extents (" << half_.x() << ", " << half_.y() << ", " << half_.z() << ")";
  return s.str();
}

Capsule::Capsule(double radius, double half_length) : radius_(radius), half_length_(half_length) {
  check_length(radius, "a capsule's radius", false);
  check_length(half_length, "a capsule's half length", true);
}

double Capsule::local_distance(const Vec3& p, Vec3& normal) const {
  const Vec3 axis_point(0, 0, std::clamp(p.z(), -half_length_, half_length_));
  const Vec3 r = p - axis_point;
  const double len = r.norm();
  normal = len > 0 ? Vec3(r / len) : radial_direction(p);
  return len - radius_;
}

std::string Capsule::describe() const {
  return "capsule of radius " + std::to_string(radius_) + " and half length " + std::to_string(half_length_);
}

Cylinder::Cylinder(double radius, double half_length) : radius_(radius), half_length_(half_length) {
  check_length(radius, "a cylinder's radius", false);
  check_length(half_length, "a cylinder's half length", false);
}

double Cylinder::local_distance(const Vec3& p, Vec3& normal) const {
  const Vec3 radial = radial_direction(p);
  const double q_r = std::hypot(p.x(), p.y()) - radius_, q_z = std::abs(p.z()) - half_length_;
  const Vec3 axial = sign(p.z()) * Vec3::UnitZ();
  if (q_r > 0 || q_z > 0) {  // outside: nearest is the mantle, a cap or their rim
    const double a = std::max(q_r, 0.0), b = std::max(q_z, 0.0), d = std::hypot(a, b);
    normal = (a * radial + b * axial) / d;
    return d;
  }
  normal = q_r > q_z ? radial : axial;
  return std::max(q_r, q_z);
}

std::string Cylinder::describe() const {
  return "cylinder of radius " + std::to_string(radius_) + " and half length " + std::to_string(half_length_);
}

}  // namespace corotate
