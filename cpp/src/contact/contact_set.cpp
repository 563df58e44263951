#include "corotate/contact/contact_set.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate {

void ContactSettings::validate() const {
  if (!std::isfinite(stiffness_scale) || stiffness_scale <= 0) {
    std::ostringstream msg;
    msg << "contact stiffness_scale must be positive and finite, not " << stiffness_scale;
    throw InvalidInput(msg.str());
  }
  if (!std::isfinite(friction_velocity) || friction_velocity <= 0) {
    std::ostringstream msg;
    msg << "friction_velocity must be positive and finite [m/s], not " << friction_velocity;
    throw InvalidInput(msg.str());
  }
}

void ContactSet::set_node_properties(Vec masses, Vec node_stiffness) {
  masses_ = std::move(masses);
  node_stiffness_ = std::move(node_stiffness);
}

void ContactSet::set_nodes(std::vector<Index> nodes) { nodes_ = std::move(nodes); }

void ContactSet::set_settings(const ContactSettings& settings) {
  settings.validate();
  settings_ = settings;
}

namespace {

// Where the path from a to b (obstacle frame) first touches the surface: the parameter t in
// [0, 1], or -1 when it stays outside. Sphere tracing: the signed distance is a lower bound
// of the distance to the surface, so advancing by it never steps over the surface.
double first_touch(const Obstacle& obstacle, const Vec3& a, const Vec3& b, double distance_at_a) {
  const double length = (b - a).norm();
  const double tolerance = 1e-3 * length + 1e-12;
  if (distance_at_a <= tolerance) return 0;
  if (distance_at_a > length) return -1;
  double t = 0, d = distance_at_a;
  Vec3 normal;
  for (int it = 0; it < 64; ++it) {
    t += d / length;
    if (t > 1) return -1;
    d = obstacle.local_distance(a + t * (b - a), normal);
    if (d <= tolerance) return t;
  }
  return t;  // a grazing path that creeps on: treat as touching (conservative)
}

}  // namespace

void ContactSet::detect(const std::vector<ObstacleLink>& links, const std::vector<Pose>& poses, const Nodes& x,
                        const Nodes& v, const Vec3& gravity, double dt) {
  dt_ = dt;
  // The multipliers of the last step's contacts, by node, to carry over.
  previous_.swap(contacts_);
  contacts_.clear();
  if (first_contact_.size() != static_cast<size_t>(x.cols())) first_contact_.assign(x.cols(), -1);
  for (size_t c = previous_.size(); c-- > 0;) first_contact_[previous_[c].node] = static_cast<int>(c);
  const auto carried = [&](Index node, int obstacle) {
    for (int c = first_contact_[node]; c >= 0 && c < static_cast<int>(previous_.size()) && previous_[c].node == node;
         ++c)
      if (previous_[c].obstacle == obstacle) return previous_[c].multiplier;
    return 0.0;
  };

  for (int j = 0; j < static_cast<int>(links.size()); ++j) {
    const Obstacle& obstacle = *links[j].obstacle;
    const Pose& end = poses[j];
    const Pose& start = links[j].seen ? links[j].last_pose : end;
    for (Index i : nodes_) {
      const Vec3 xi = x.col(i);
      const Vec3 a = start.to_local(xi), b = end.to_local(xi + dt * v.col(i) + dt * dt * gravity);
      Vec3 normal;
      const double distance_at_a = obstacle.local_distance(a, normal);
      const double lambda = previous_.empty() ? 0.0 : carried(i, j);
      const double t = first_touch(obstacle, a, b, distance_at_a);
      if (t < 0 && lambda == 0) continue;
      // The tangent plane where the path first touches (at its start when it does not touch
      // but the contact carried force: the node rests on the surface).
      const Vec3 p = a + std::max(t, 0.0) * (b - a);
      const double d = obstacle.local_distance(p, normal);
      const Vec3 surface_local = p - d * normal;
      Contact c;
      c.node = i;
      c.obstacle = j;
      c.normal = end.rotation * normal;
      c.point = end.to_world(surface_local);
      const Vec3 obstacle_velocity = (c.point - start.to_world(surface_local)) / dt;
      c.slip_origin = xi + dt * obstacle_velocity;
      c.stiffness = settings_.stiffness_scale * (masses_[i] / (dt * dt) + node_stiffness_[i]);
      c.multiplier = lambda;
      c.predicted = xi + dt * v.col(i) + dt * dt * gravity;
      const double predicted_gap = c.normal.dot(c.predicted - c.point);
      c.friction_force = links[j].friction * std::max(0.0, lambda - c.stiffness * predicted_gap);
      contacts_.push_back(c);
    }
  }
  for (const Contact& c : previous_) first_contact_[c.node] = -1;  // back to all -1 (no allocation)
  // Sorted by node, so that the next step finds a node's contacts side by side.
  std::sort(contacts_.begin(), contacts_.end(),
            [](const Contact& p, const Contact& q) { return p.node != q.node ? p.node < q.node : p.obstacle < q.obstacle; });
}

namespace {
// The smoothed friction's F0 and f1 = F0' and f1' (see the header), s >= 0.
double friction_potential(double s, double eps) { return s < eps ? s * s / eps - s * s * s / (3 * eps * eps) : s - eps / 3; }
}  // namespace

double ContactSet::energy_of(const Contact& c, const Vec3& y) const {
  const double push = std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(y - c.point));
  double e = push * push / (2 * c.stiffness);
  if (c.friction_force > 0) {
    const Vec3 slip = y - c.slip_origin;
    const Vec3 u = slip - c.normal.dot(slip) * c.normal;
    e += c.friction_force * friction_potential(u.norm(), settings_.friction_velocity * dt_);
  }
  return e;
}

Vec3 ContactSet::force_of(const Contact& c, const Vec3& y, Mat3* hessian) const {
  const double push = std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(y - c.point));
  Vec3 f = push * c.normal;
  if (hessian) {
    if (push > 0) *hessian = c.stiffness * c.normal * c.normal.transpose();
    else hessian->setZero();
  }
  if (c.friction_force > 0) {
    const double eps = settings_.friction_velocity * dt_;
    const Mat3 tangential = Mat3::Identity() - c.normal * c.normal.transpose();
    const Vec3 u = tangential * (y - c.slip_origin);
    const double s = u.norm();
    if (s >= eps) {
      const Vec3 dir = u / s;
      f -= c.friction_force * dir;
      if (hessian) *hessian += (c.friction_force / s) * (tangential - dir * dir.transpose());
    } else {
      f -= c.friction_force * (2 / eps - s / (eps * eps)) * u;
      if (hessian) {
        *hessian += c.friction_force * (2 / eps - s / (eps * eps)) * tangential;
        if (s > 0) *hessian -= (c.friction_force / (eps * eps * s)) * u * u.transpose();
      }
    }
  }
  return f;
}

double ContactSet::energy(const Nodes& y) const {
  double e = 0;
  for (const Contact& c : contacts_) e += energy_of(c, y.col(c.node));
  return e;
}

void ContactSet::add_forces(const Nodes& y, Nodes& f) const {
  for (const Contact& c : contacts_) f.col(c.node) += force_of(c, y.col(c.node), nullptr);
}

void ContactSet::add_stiffness(const Nodes& y, double scale, BlockSparseMatrix& A) const {
  Mat3 h;
  for (const Contact& c : contacts_) {
    force_of(c, y.col(c.node), &h);
    A.block(A.diagonal_block(c.node)) += scale * h;
  }
}

void ContactSet::add_stiffness(const Nodes& y, double scale, SinglePrecisionSymmetric& A) const {
  Mat3 h;
  for (const Contact& c : contacts_) {
    force_of(c, y.col(c.node), &h);
    A.add_to_diagonal_block(c.node, scale * h);
  }
}

void ContactSet::add_linearized(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix* A,
                                SinglePrecisionSymmetric* single) const {
  Mat3 h;
  for (const Contact& c : contacts_) {
    const Vec3 force = force_of(c, c.predicted, &h);
    f.col(c.node) += force + h * (c.predicted - y.col(c.node));
    if (single) single->add_to_diagonal_block(c.node, scale * h);
    else A->block(A->diagonal_block(c.node)) += scale * h;
  }
}

void ContactSet::commit(const Nodes& x_new) {
  forces_.resize(3, static_cast<Index>(contacts_.size()));
  for (size_t k = 0; k < contacts_.size(); ++k) {
    Contact& c = contacts_[k];
    const Vec3 y = x_new.col(c.node);
    forces_.col(static_cast<Index>(k)) = force_of(c, y, nullptr);
    c.multiplier = std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(y - c.point));
  }
}

void ContactSet::reset() {
  contacts_.clear();
  previous_.clear();
  forces_.resize(3, 0);
}

}  // namespace corotate
