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

void ContactSet::set_node_properties(Vec masses, Vec node_stiffness, Vec node_sizes) {
  masses_ = std::move(masses);
  node_stiffness_ = std::move(node_stiffness);
  node_sizes_ = std::move(node_sizes);
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
// How near the surface counts as touching for a path from a to b.
double touch_tolerance(const Vec3& a, const Vec3& b) { return 1e-3 * (b - a).norm() + 1e-12; }

double first_touch(const Obstacle& obstacle, const Vec3& a, const Vec3& b, double distance_at_a) {
  const double length = (b - a).norm();
  const double tolerance = touch_tolerance(a, b);
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
      const Vec3 free_flight = xi + dt * v.col(i) + dt * dt * gravity;
      Vec3 a = start.to_local(xi), normal;
      const Vec3 b = end.to_local(free_flight);
      // A deforming surface (another body's) is taken at the end of the step; relative to
      // it the node starts displaced by the surface's own motion near it over the step.
      if (obstacle.deforms()) {
        const double d = obstacle.local_distance(a, normal);
        a += dt * obstacle.local_velocity(a - d * normal);
      }
      const double distance_at_a = obstacle.local_distance(a, normal);
      const double lambda = previous_.empty() ? 0.0 : carried(i, j);
      const double t = first_touch(obstacle, a, b, distance_at_a);
      // A new contact needs a path that enters: one that starts on the surface and moves
      // along it or away (a side resting against a wall) touches without pushing, and as a
      // contact it would only cost the active set a second solve.
      if (lambda == 0 && (t < 0 || (t == 0 && distance_at_a > -touch_tolerance(a, b) &&
                                    obstacle.local_distance(b, normal) >= -touch_tolerance(a, b))))
        continue;
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
      const Vec3 obstacle_velocity =
          (c.point - start.to_world(surface_local)) / dt + end.rotation * obstacle.local_velocity(surface_local);
      c.slip_origin = xi + dt * obstacle_velocity;
      c.stiffness = settings_.stiffness_scale * (masses_[i] / (dt * dt) + node_stiffness_[i]);
      c.multiplier = lambda;
      // An impact: a new contact that closes at more than 1 % of the node's size per step
      // (not a resting node that touches again under gravity's dt^2 g).
      c.impact = lambda == 0 && c.normal.dot(v.col(i) - obstacle_velocity) * dt < -1e-2 * node_sizes_[i];
      // The normal force friction scales with: the one the contact carried over the last
      // step (none in a contact's first step: a prediction from the penetration the step
      // would have without contact overestimates an impact's force by the stiffness scale).
      c.friction_force = links[j].friction * lambda;
      // The stuck regime's width: friction_velocity * dt, or wider where that would make the
      // friction stiffer (2 mu N / eps) than the normal contact (k): a sticking node then
      // creeps by at most about the normal contact's own penetration, and the system keeps
      // the conditioning of the normal contact.
      c.slip_width = std::max(settings_.friction_velocity * dt, c.friction_force / c.stiffness);
      contacts_.push_back(c);
    }
  }
  for (const Contact& c : previous_) first_contact_[c.node] = -1;  // back to all -1 (no allocation)
  // Sorted by node, so that the next step finds a node's contacts side by side.
  std::sort(contacts_.begin(), contacts_.end(), [](const Contact& p, const Contact& q) {
    return p.node != q.node ? p.node < q.node : p.obstacle < q.obstacle;
  });
}

namespace {
// The smoothed friction's F0 and f1 = F0' and f1' (see the header), s >= 0.
double friction_potential(double s, double eps) {
  return s < eps ? s * s / eps - s * s * s / (3 * eps * eps) : s - eps / 3;
}
}  // namespace

double ContactSet::energy_of(const Contact& c, const Vec3& y) const {
  if (!c.active) return 0;
  const double push = std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(y - c.point));
  double e = push * push / (2 * c.stiffness);
  if (c.friction_force > 0) {
    const Vec3 slip = y - c.slip_origin;
    const Vec3 u = slip - c.normal.dot(slip) * c.normal;
    e += c.friction_force * friction_potential(u.norm(), c.slip_width);
  }
  return e;
}

Vec3 ContactSet::normal_force(const Contact& c, const Vec3& y, Mat3* hessian) {
  const double push = std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(y - c.point));
  if (hessian) {
    if (push > 0) *hessian = c.stiffness * c.normal * c.normal.transpose();
    else hessian->setZero();
  }
  return push * c.normal;
}

Vec3 ContactSet::friction(const Contact& c, const Vec3& y, Mat3* hessian) {
  const Mat3 tangential = Mat3::Identity() - c.normal * c.normal.transpose();
  const Vec3 u = tangential * (y - c.slip_origin);
  const double s = u.norm(), eps = c.slip_width, mu_n = c.friction_force;
  if (s >= eps) {  // sliding: mu N against the slip
    const Vec3 dir = u / s;
    if (hessian) *hessian = (mu_n / s) * (tangential - dir * dir.transpose());
    return -mu_n * dir;
  }
  const double slope = mu_n * (2 / eps - s / (eps * eps));  // mu N f1(s) / s
  if (hessian) {
    *hessian = slope * tangential;
    if (s > 0) *hessian -= (mu_n / (eps * eps * s)) * u * u.transpose();
  }
  return -slope * u;
}

Vec3 ContactSet::force_of(const Contact& c, const Vec3& y, Mat3* hessian) const {
  if (!c.active) {
    if (hessian) hessian->setZero();
    return Vec3::Zero();
  }
  Vec3 f = normal_force(c, y, hessian);
  if (c.friction_force > 0) {
    Mat3 h;
    f += friction(c, y, hessian ? &h : nullptr);
    if (hessian) *hessian += h;
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

void ContactSet::add_linearized(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix* A,
                                SinglePrecisionSymmetric* single) const {
  Mat3 h;
  for (const Contact& c : contacts_) {
    if (!c.active) continue;
    const Vec3 yc = y.col(c.node);
    // The normal force as the linear spring it is while the contact holds, (lambda - k g) n
    // with g = n . (y - p): its max(0, .) is the active set's business (update_active), so
    // a contact whose node the prediction puts outside still holds where the answer is inside.
    f.col(c.node) += (c.multiplier - c.stiffness * c.normal.dot(yc - c.point)) * c.normal;
    h = c.stiffness * c.normal * c.normal.transpose();
    if (c.friction_force > 0) {
      // Friction as the damping of its secant at the slip the node starts the step with:
      // force -(mu N f1(s) / s) u at the new slip u. One linear solve cannot follow the
      // smoothed law's kink (its tangent, extrapolated from a sticking slip, asks for many
      // times mu N and overshoots); the secant never exceeds mu N by more than the slip
      // grows in the step, and it only ever dissipates.
      const Mat3 tangential = Mat3::Identity() - c.normal * c.normal.transpose();
      const Vec3 u = tangential * (yc - c.slip_origin);
      const double s = u.norm(), eps = c.slip_width;
      const double damping = c.friction_force * (s >= eps ? 1 / s : 2 / eps - s / (eps * eps));
      f.col(c.node) -= damping * u;
      h += damping * tangential;
    }
    if (single) single->add_to_diagonal_block(c.node, scale * h);
    else A->block(A->diagonal_block(c.node)) += scale * h;
  }
}

bool ContactSet::has_impacts() const {
  for (const Contact& c : contacts_)
    if (c.impact) return true;
  return false;
}

bool ContactSet::update_active(const Nodes& x_new) {
  bool changed = false;
  for (Contact& c : contacts_) {
    const double gap = c.normal.dot(x_new.col(c.node) - c.point);
    // Released where its linear force pulls (gap > lambda / k) and the node ended clearly off
    // the plane: a contact resting on the surface ends within an inexact solve's noise of
    // it, where the sign of its force would flip from pass to pass.
    const double noise = 1e-3 * node_sizes_[c.node];
    const bool active = c.active ? gap <= std::max(c.multiplier / c.stiffness, noise) : gap < -noise;
    changed = changed || active != c.active;
    c.active = active;
  }
  return changed;
}

void ContactSet::commit(const Nodes& x_new) {
  forces_.resize(3, static_cast<Index>(contacts_.size()));
  for (size_t k = 0; k < contacts_.size(); ++k) {
    Contact& c = contacts_[k];
    const Vec3 y = x_new.col(c.node);
    forces_.col(static_cast<Index>(k)) = force_of(c, y, nullptr);
    c.multiplier = c.active ? std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(y - c.point)) : 0.0;
  }
}

void ContactSet::reset() {
  contacts_.clear();
  previous_.clear();
  forces_.resize(3, 0);
}

}  // namespace corotate
