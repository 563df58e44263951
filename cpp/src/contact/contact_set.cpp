#include "corotate/contact/contact_set.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "corotate/contact/closest_point_on_triangle.hpp"
#include "corotate/contact/closest_points_on_segments.hpp"
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
  auto table = std::make_shared<UnitTable>();
  table->masses = std::move(masses);
  table->stiffness = std::move(node_stiffness);
  table->sizes = std::move(node_sizes);
  nodes_table_ = std::move(table);
}

void ContactSet::set_nodes(std::vector<Index> nodes) { nodes_ = std::move(nodes); }

const ContactPoints ContactSet::kNoPoints;

void ContactSet::set_points(ContactPoints points) {
  contacts_.clear();
  previous_.clear();
  if (points.empty()) {
    table_.reset();
    return;
  }
  auto table = std::make_shared<UnitTable>();
  const UnitTable& node = *nodes_table_;
  const Index count = points.size();
  table->masses.resize(count);
  table->stiffness.resize(count);
  table->sizes.resize(count);
  // The nodes in series (a point alone on its nodes; share_among_points divides them among
  // the step's contacts).
  for (Index p = 0; p < count; ++p) {
    double compliance = 0, flexibility = 0, size = 0;
    for (int k = 0; k < points.per_point; ++k) {
      const Index n = points.nodes[p * points.per_point + k];
      const double w = points.weights[p * points.per_point + k];
      compliance += w * w / std::max(node.masses[n], 1e-300);
      flexibility += w * w / std::max(node.stiffness[n], 1e-300);
      size += std::abs(w) * node.sizes[n];
    }
    table->masses[p] = 1 / compliance;
    table->stiffness[p] = 1 / flexibility;
    table->sizes[p] = size;
  }
  // Groups: points with the same nodes, side by side.
  std::vector<Index> order(static_cast<size_t>(count));
  for (Index p = 0; p < count; ++p) order[p] = p;
  const auto nodes_of = [&](Index p) { return points.nodes.begin() + p * points.per_point; };
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) {
    return std::lexicographical_compare(nodes_of(a), nodes_of(a) + points.per_point, nodes_of(b),
                                        nodes_of(b) + points.per_point);
  });
  for (Index k = 0; k < count; ++k) {
    const Index p = order[k];
    if (k == 0 || !std::equal(nodes_of(p), nodes_of(p) + points.per_point, nodes_of(order[k - 1]))) {
      table->group_start.push_back(static_cast<int>(k));
      table->group_spread.push_back(0.0);
    }
    double spread = 0;
    for (int j = 0; j < points.per_point; ++j) spread += std::abs(points.weights[p * points.per_point + j]);
    table->group_spread.back() = std::max(table->group_spread.back(), spread);
  }
  table->group_start.push_back(static_cast<int>(count));
  table->group_order = std::move(order);
  table->points = std::move(points);
  table_ = std::move(table);
}

bool ContactSet::group_out_of_reach(const UnitTable& table, int g, const Obstacle& obstacle, const Pose& start,
                                    const Pose& end, const Nodes& x, const Nodes& v, const Vec3& gravity,
                                    double dt) const {
  // A point of the group is p = c + sum_k w_k (x_k - c) for the nodes' centre c, so it lies
  // within spread * r of c (r: the nodes' largest distance from c), and moves over the step
  // by at most spread * dt * (their largest speed) + dt^2 |g|. In the obstacle's frame c
  // itself moves by m between the two poses. The signed distance changes by at most the
  // distance moved, so when the obstacle is farther from c (at the start pose) than all
  // that, no point of the group can touch it within the step.
  const ContactPoints& points = table.points;
  const Index* nodes = &points.nodes[table.group_order[table.group_start[g]] * points.per_point];
  Vec3 c = Vec3::Zero();
  for (int k = 0; k < points.per_point; ++k) c += x.col(nodes[k]);
  c /= points.per_point;
  double r = 0, speed = 0;
  for (int k = 0; k < points.per_point; ++k) {
    r = std::max(r, (x.col(nodes[k]) - c).norm());
    speed = std::max(speed, v.col(nodes[k]).norm());
  }
  const double spread = table.group_spread[g];
  const Vec3 local = start.to_local(c);
  const double reach = spread * (r + dt * speed) + dt * dt * gravity.norm() + (end.to_local(c) - local).norm();
  Vec3 normal;
  return obstacle.local_distance(local, normal) > 1.01 * reach + 1e-12;
}

Nodes ContactSet::unit_positions(const Nodes& x) const {
  if (!table_) return x;
  const ContactPoints& points = table_->points;
  Nodes out(3, points.size());
  for (Index p = 0; p < points.size(); ++p) out.col(p) = points.of(p, x);
  return out;
}

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

// Whether a node at x with velocity v surely makes no new contact with a part in this step:
// consider() takes the part's surface where the step ends and the node's path from x, moved
// by the surface's velocity near it (at most dt |mean velocity| + spread), to its free
// flight's end b; a contact needs the path to start no farther from the surface than its
// length (first_touch). The surface lies inside its vertices' box, so a start farther from
// the box than the longest such path, with room for the touch tolerance, is out of reach:
// no nearest-point query for bodies apart.
bool out_of_part_reach(const Vec3& x, const Vec3& v, const PartSurface& part, const Vec3& gravity, double dt) {
  const double shift = dt * part.mean_velocity.norm() + part.spread;
  const double path = (dt * v + dt * dt * gravity).norm() + shift;
  return part.end_box.exteriorDistance(x) > 1.01 * (path + shift) + 1e-9;
}

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

void ContactSet::set_parts(std::vector<int> part_of_node, std::vector<PartSurface> parts, double friction,
                           const BlockSparseMatrix* neighbourhoods) {
  part_of_node_ = std::move(part_of_node);
  parts_ = std::move(parts);
  edge_offset_.clear();
  num_edges_ = 0;
  for (PartSurface& part : parts_) {
    if (!part.edges) part.edges = std::make_shared<const SurfaceEdges>(surface_edges(part.triangles));
    edge_offset_.push_back(num_edges_);
    num_edges_ += part.edges->size();
  }
  neighbourhoods_ = neighbourhoods;
  vertex_of_node_.assign(part_of_node_.size(), -1);
  for (const PartSurface& part : parts_)
    for (size_t k = 0; k < part.nodes.size(); ++k) vertex_of_node_[part.nodes[k]] = static_cast<int>(k);
  part_friction_ = friction;
  contacts_.clear();
  previous_.clear();
}

void ContactSet::set_fixed_nodes(Index num_nodes, const std::vector<Index>& fixed) {
  fixed_.assign(static_cast<size_t>(num_nodes), 0);
  for (Index i : fixed) fixed_[static_cast<size_t>(i)] = 1;
}

template <class Carried>
void ContactSet::consider(Index i, const Vec3& xi, const Vec3& vi, const Obstacle& surface, int id, const Pose& start,
                          const Pose& end, double friction, const Nodes& x, const Vec3& gravity, double dt,
                          const Carried& carried, const PartSurface* part) {
  const Vec3 free_flight = xi + dt * vi + dt * dt * gravity;
  Vec3 a = start.to_local(xi), normal;
  const Vec3 b = end.to_local(free_flight);
  // A deforming surface (a part's, or a mesh whose vertices move) is taken at the end of
  // the step; relative to it the node starts displaced by the surface's own motion near it.
  if (surface.deforms()) {
    const double d = surface.local_distance(a, normal);
    a += dt * surface.local_velocity(a - d * normal);
  }
  const double distance_at_a = surface.local_distance(a, normal);
  const double lambda = carried(i, id);
  const double t = first_touch(surface, a, b, distance_at_a);
  // A new contact needs a path that enters: one that starts on the surface and moves
  // along it or away (a side resting against a wall) touches without pushing, and as a
  // contact it would only cost the active set a second solve.
  if (lambda == 0 && (t < 0 || (t == 0 && distance_at_a > -touch_tolerance(a, b) &&
                                surface.local_distance(b, normal) >= -touch_tolerance(a, b))))
    return;
  // The tangent plane where the path first touches; where it does not touch but the contact
  // carried force, at the path's end: a node resting against a wall, or one the obstacle
  // left (a tool lifted or swept away within the step: at the path's start the plane would
  // still hold the node where the tool no longer is, and push it for a step).
  const Vec3 p = t >= 0 ? Vec3(a + t * (b - a)) : b;
  const double d = surface.local_distance(p, normal);
  const Vec3 surface_local = p - d * normal;
  Contact c;
  c.node = i;
  c.obstacle = id;
  c.normal = end.rotation * normal;
  c.point = end.to_world(surface_local);
  const Vec3 surface_velocity =
      (c.point - start.to_world(surface_local)) / dt + end.rotation * surface.local_velocity(surface_local);
  if (part) {
    // The point moves with its triangle: the gap and the slip are of r = y_i - sum w_j y_j.
    std::array<int, 3> corners;
    part->mesh->nearest(surface_local, corners, c.weights);
    for (int k = 0; k < 3; ++k) c.partners[k] = part->nodes[corners[k]];
    // On another part's edge or corner the surface's normal is a cone: a face that rests on
    // an edge is pushed along its own normal, not along the edge's bisector (which would
    // push it off sideways, without friction for ever). So there the node's own surface
    // normal decides, where it lies within the cone's reach.
    const bool on_face = c.weights.minCoeff() > 1e-9;
    const int own = table_ ? -1 : vertex_of_node_[i];
    if (!on_face && own >= 0) {
      const Vec3 facing = -parts_[part_of_node_[i]].mesh->vertex_normal(own);
      if (facing.dot(c.normal) > 0.5) c.normal = facing;
    }
    c.anchor = Vec3::Zero();
    c.slip_origin = relative(c, x);
  } else {
    c.anchor = c.point;
    c.slip_origin = xi + dt * surface_velocity;
  }
  // A contact point that would only graze the surface (a new contact that starts within
  // gravity's dt^2 g of it and whose free flight ends no deeper) starts released: a fine
  // surface's many points on one coarse element cannot all rest on the floor at once, and
  // those the last step left just above it would otherwise be held onto it for a first solve
  // and released in a second, at every step. The linearised step's active set takes it in if
  // the point ends inside.
  const double graze = 1.5 * dt * dt * gravity.norm();
  if (table_ && lambda == 0 && distance_at_a <= graze && -surface.local_distance(b, normal) <= graze) c.active = false;
  keep(c, lambda, friction, surface_velocity, vi, dt, unit(i));
}

void ContactSet::keep(Contact& c, double lambda, double friction, const Vec3& surface_velocity, const Vec3& vi,
                      double dt, const Unit& unit) {
  c.stiffness = settings_.stiffness_scale * (unit.mass / (dt * dt) + unit.stiffness);
  c.multiplier = lambda;
  c.size = unit.size;
  // An impact: a new contact that closes at more than 1 % of the node's size per step
  // (not a resting node that touches again under gravity's dt^2 g); or any contact with a
  // surface that moves by as much (a tool pushing or sweeping the body). Both ask the step
  // for an accurate solve: the multiplier update lambda - k g(x_new) multiplies the solve's
  // error in x_new by the contact stiffness, and a loose solve under a moving tool left
  // multipliers (and reported forces) tens of times the real ones, which the next step then
  // applied.
  const double closing = c.normal.dot(vi - surface_velocity) * dt;
  c.moving_surface = surface_velocity.norm() * dt > 1e-2 * unit.size;
  c.impact = (lambda == 0 && closing < -1e-2 * unit.size) || c.moving_surface;
  // The normal force friction scales with: the one the contact carried over the last
  // step (none in a contact's first step: a prediction from the penetration the step
  // would have without contact overestimates an impact's force by the stiffness scale).
  c.friction_force = friction * lambda;
  // The stuck regime's width: friction_velocity * dt, or wider where that would make the
  // friction stiffer (2 mu N / eps) than the normal contact (k): a sticking node then
  // creeps by at most about the normal contact's own penetration, and the system keeps
  // the conditioning of the normal contact.
  c.slip_width = std::max(settings_.friction_velocity * dt, c.friction_force / c.stiffness);
  contacts_.push_back(c);
}

void ContactSet::share_among_points(double dt) {
  if (!table_ || contacts_.empty()) return;
  const ContactPoints& points = table_->points;
  const UnitTable& node = *nodes_table_;
  std::vector<double>& load = load_.value;  // all zero between calls
  if (load.size() != static_cast<size_t>(node.masses.size())) load.assign(node.masses.size(), 0.0);
  const auto for_each_node = [&](const Contact& c, auto&& f) {
    for (int k = 0; k < points.per_point; ++k)
      f(points.nodes[c.node * points.per_point + k], points.weights[c.node * points.per_point + k]);
  };
  for (const Contact& c : contacts_) for_each_node(c, [&](Index n, double w) { load[n] += w * w; });
  for (Contact& c : contacts_) {
    double compliance = 0, flexibility = 0;
    for_each_node(c, [&](Index n, double w) {
      compliance += w * w * load[n] / std::max(node.masses[n], 1e-300);
      flexibility += w * w * load[n] / std::max(node.stiffness[n], 1e-300);
    });
    c.stiffness = settings_.stiffness_scale * (1 / (compliance * dt * dt) + 1 / flexibility);
    c.slip_width = std::max(settings_.friction_velocity * dt, c.friction_force / c.stiffness);
  }
  for (const Contact& c : contacts_) for_each_node(c, [&](Index n, double) { load[n] = 0; });
}

template <class Carried>
void ContactSet::consider_self(Index i, const Nodes& x, const Nodes& v, const Vec3& gravity, double dt,
                               const Carried& carried) {
  const int p = part_of_node_[i];
  const PartSurface& part = parts_[p];
  const int id = -1 - p;
  const double lambda = carried(i, id);
  const double size = unit_size(i);
  const double depth = 0.25 * size;  // how far behind a triangle a node may start and be pushed back
  const Vec3 xi = x.col(i);
  const Vec3 b = xi + dt * v.col(i) + dt * dt * gravity;
  const Vec3 own_normal = part.mesh->vertex_normal(vertex_of_node_[i]);
  // Every triangle the node's path can cross relative to it lies within this reach of b.
  // (The relative path is at most dt |v_i - mean| + spread long, the margin below half that.)
  const double reach =
      depth + dt * dt * gravity.norm() + 1.5 * (dt * (v.col(i) - part.mean_velocity).norm() + part.spread);
  part.mesh->triangles_near(b, reach, candidates_.value);
  // The node's own neighbourhood (the nodes it shares an element with), marked for O(1) tests.
  std::vector<int>& neighbour = neighbour_stamp_.value;
  const int stamp = static_cast<int>(i) + 1;
  for (int k = neighbourhoods_->row_start()[i]; k < neighbourhoods_->row_start()[i + 1]; ++k)
    neighbour[neighbourhoods_->columns()[k]] = stamp;
  struct Touch {
    int triangle = -1;
    double t = 2;  // where along the path; 1 for a carried contact's nearest triangle
    Vec3 weights, normal;
    bool ahead = false;  // the path ends in front of the triangle
  } hit, nearest;
  double nearest2 = reach * reach;
  for (int t : candidates_.value) {
    const std::array<int, 3>& tri = part.triangles[t];
    std::array<Index, 3> corner;
    bool near_node = false;
    for (int k = 0; k < 3; ++k) {
      corner[k] = part.nodes[tri[k]];
      near_node = near_node || neighbour[corner[k]] == stamp;
    }
    if (near_node) continue;
    const Vec3 e0 = part.ends.col(tri[0]), e1 = part.ends.col(tri[1]), e2 = part.ends.col(tri[2]);
    Vec3 normal = (e1 - e0).cross(e2 - e0);
    if (normal.norm() == 0) continue;
    normal.normalize();
    if (lambda > 0) {  // a contact that carried force holds on to the nearest triangle
      const TrianglePoint q = closest_point_on_triangle(b, e0, e1, e2);
      const double d2 = (b - q.point).squaredNorm();
      if (d2 < nearest2) nearest2 = d2, nearest = {t, 1, q.barycentric, normal, false};
    }
    // Only surfaces that face each other touch (the triangles of the node's own side of a
    // thin wall lie behind it, facing the same way).
    if (own_normal.dot(normal) >= 0) continue;
    // The node's start, moved by the triangle's own motion where the node lies over it.
    const TrianglePoint q0 = closest_point_on_triangle(xi, x.col(corner[0]), x.col(corner[1]), x.col(corner[2]));
    Vec3 a = xi;
    for (int k = 0; k < 3; ++k) a += q0.barycentric[k] * (part.ends.col(tri[k]) - x.col(corner[k]));
    const double da = normal.dot(a - e0), db = normal.dot(b - e0);
    // Free flight is only a prediction: a surface that rests on something does not fall by
    // dt^2 g, and the node's own elastic forces are left out. So a node that ends less than
    // half its relative path (plus dt^2 g) in front of the triangle touches it too, at the
    // end of its path: its spring pushes only if the step takes it there.
    const double margin = 0.5 * (b - a).norm() + dt * dt * gravity.norm();
    if (db >= margin || da < -depth) continue;  // ends clearly in front, or started deep behind
    const double along = da <= 0 ? 0.0 : db < 0 ? da / (da - db) : 1.0;
    Vec3 on_plane = a + along * (b - a);
    on_plane -= normal.dot(on_plane - e0) * normal;
    const TrianglePoint q = closest_point_on_triangle(on_plane, e0, e1, e2);
    if ((on_plane - q.point).squaredNorm() > 1e-6 * size * size) continue;  // passes beside the triangle
    if (along < hit.t) hit = {t, along, q.barycentric, normal, db >= 0};
  }
  const Touch& touch = hit.triangle >= 0 ? hit : nearest;
  if (touch.triangle < 0) return;
  Contact c;
  c.node = i;
  c.obstacle = id;
  Vec3 surface_velocity = Vec3::Zero();
  c.point.setZero();
  for (int k = 0; k < 3; ++k) {
    const int vertex = part.triangles[touch.triangle][k];
    c.partners[k] = part.nodes[vertex];
    c.point += touch.weights[k] * part.ends.col(vertex);
    surface_velocity += touch.weights[k] * part.velocities.col(vertex);
  }
  c.weights = touch.weights;
  c.normal = touch.normal;
  c.anchor = Vec3::Zero();
  c.slip_origin = relative(c, x);
  // A path that ends in front is left to the active set (update_active takes the contact in
  // if the node ends behind the triangle): as a spring it would pull the node onto it.
  c.active = !(touch.ahead && lambda == 0);
  keep(c, lambda, part_friction_, surface_velocity, v.col(i), dt, unit(i));
}

void ContactSet::consider_edges(int p, int q, const Nodes& x, const Nodes& v, const Vec3& gravity, double dt,
                                const std::vector<std::pair<Index, double>>& carried) {
  const PartSurface& mine = parts_[p];
  const PartSurface& other = parts_[q];
  const SurfaceEdges& edges = *mine.edges;
  const SurfaceEdges& other_edges = *other.edges;
  const bool self = p == q;
  const double fall = dt * dt * gravity.norm();
  // The parts' boxes at the step's end: edges of one that stay out of reach of the other's
  // box are skipped before any range query.
  const Vec3 other_low = other.ends.rowwise().minCoeff(), other_high = other.ends.rowwise().maxCoeff();
  std::vector<int>& near = candidate_edges_.value;
  const std::vector<char>& touching = touching_.value;
  std::vector<int>& neighbour_stamp = neighbour_stamp_.value;  // (sized by detect)
  std::vector<int>& edge_stamp = edge_stamp_.value;
  for (int e1 = 0; e1 < edges.size(); ++e1) {
    const int va = edges.vertices[e1][0], vb = edges.vertices[e1][1];
    const Index a = mine.nodes[va], b = mine.nodes[vb];
    const Vec3 A = mine.ends.col(va), B = mine.ends.col(vb);
    const double size = 0.5 * (unit_size(a) + unit_size(b));
    const double depth = 0.25 * size;
    const double travel =
        dt * std::max((v.col(a) - other.mean_velocity).norm(), (v.col(b) - other.mean_velocity).norm());
    const double reach = depth + fall + 1.5 * (travel + other.spread);
    if (((A.cwiseMin(B).array() - reach) > other_high.array()).any() ||
        ((A.cwiseMax(B).array() + reach) < other_low.array()).any())
      continue;
    // (A touching node, see below, rules the edge out before its range query.)
    if (touching[a] || touching[b] || !convex_edge(edges, e1, mine.ends, mine.normals.value, 1e-6)) continue;
    const Vec3 m1 = mine.normals.value.col(edges.faces[e1][0]), m2 = mine.normals.value.col(edges.faces[e1][1]);
    // The other surface's edges of the triangles near this edge, each once.
    other.mesh->triangles_near(0.5 * (A + B), 0.5 * (B - A).norm() + reach, candidates_.value);
    // Stamps unique to this edge in the whole step: its index among all parts' edges (+ 1),
    // negated for nodes (consider_self stamps them with node + 1).
    const int stamp = static_cast<int>(edge_offset_[p]) + e1 + 1;
    const int* other_stamp = edge_stamp.data() + edge_offset_[q];
    near.clear();
    for (int t : candidates_.value)
      for (int e2 : other_edges.of_triangle[t])
        if ((!self || e2 > e1) && other_stamp[e2] != stamp) {
          edge_stamp[edge_offset_[q] + e2] = stamp;
          near.push_back(e2);
        }
    if (self)  // the edge's own neighbourhood: the nodes that share an element with a or b
      for (Index i : {a, b})
        for (int k = neighbourhoods_->row_start()[i]; k < neighbourhoods_->row_start()[i + 1]; ++k)
          neighbour_stamp[neighbourhoods_->columns()[k]] = -stamp;
    for (int e2 : near) {
      const int vc = other_edges.vertices[e2][0], vd = other_edges.vertices[e2][1];
      const Index c = other.nodes[vc], d = other.nodes[vd];
      // Within one part, away from the edge's own neighbourhood.
      if (self && (neighbour_stamp[c] == -stamp || neighbour_stamp[d] == -stamp)) continue;
      // Where a node of either edge touches a surface already, its contact holds the pair
      // apart there (a face resting on a face: the rims cross at the same height, and a second
      // constraint on the same spot only makes the two fight).
      if (touching[c] || touching[d]) continue;
      const Vec3 C = other.ends.col(vc), D = other.ends.col(vd);
      const SegmentPoints nearest = closest_points_on_segments(A, B, C, D);
      const double s = nearest.s, t = nearest.t;
      // Within 2 % of an edge's end a node is where the edges meet, and its own contact
      // (consider()) holds it: the node sinks by at most 2 % of the edge before it touches.
      // (Crossings at a node, s or t within 1 % of an end, made contacts of a few newtons
      // with a normal that means nothing where two meshes' nodes coincide, and they changed
      // how a block slid on a slab by a factor of four.)
      constexpr double kEnd = 0.02;
      if (!(s > kEnd && s < 1 - kEnd && t > kEnd && t < 1 - kEnd)) continue;
      Vec3 n = (B - A).cross(D - C);
      const double sine = n.norm() / ((B - A).norm() * (D - C).norm());
      if (!(sine > 1e-3)) continue;  // (near) parallel: the edges' nodes meet the faces first
      n.normalize();
      if (!convex_edge(other_edges, e2, other.ends, other.normals.value, 1e-6)) continue;
      const Vec3 n1 = other.normals.value.col(other_edges.faces[e2][0]),
                 n2 = other.normals.value.col(other_edges.faces[e2][1]);
      if (n.dot(n1 + n2) < 0) n = -n;  // out of the other surface
      // Each edge the other surface's nearest feature: n in the other edge's normal cone (the
      // arc between its triangles' normals), -n in this one's.
      // With some slack (about 6 degrees): a face's rim lying across a ridge puts n on the
      // cone's border, and as the face bends under the contact n leaves the cone by a little,
      // which dropped the contact every other step.
      const double cone = n1.dot(n2) - 0.1, my_cone = m1.dot(m2) - 0.1;
      if (n.dot(n1) < cone || n.dot(n2) < cone || -n.dot(m1) < my_cone || -n.dot(m2) < my_cone) continue;
      Contact contact;
      contact.node = a;
      contact.own = 1 - s;
      contact.partners = {b, c, d};
      contact.weights = Vec3(-s, 1 - t, t);
      contact.obstacle = -1 - q;
      contact.edge_pair = (edge_offset_[p] + e1) * num_edges_ + edge_offset_[q] + e2;
      contact.normal = n;
      contact.anchor = Vec3::Zero();
      const auto found = std::lower_bound(carried.begin(), carried.end(), std::make_pair(contact.edge_pair, -1.0));
      const double lambda = found != carried.end() && found->first == contact.edge_pair ? found->second : 0.0;
      const Vec3 start = relative(contact, x);
      const Vec3 end = (1 - s) * A + s * B - (1 - t) * C - t * D;
      const double gap_start = n.dot(start), gap_end = n.dot(end);
      const double margin = 0.5 * (end - start).norm() + fall;
      if (lambda == 0 && (gap_end >= margin || gap_start < -depth)) continue;
      contact.point = (1 - t) * C + t * D;
      contact.slip_origin = start;
      // A pair that ends in front is left to the active set, as a self-contact's path is.
      contact.active = !(gap_end >= 0 && lambda == 0);
      const Vec3 surface_velocity = (1 - t) * other.velocities.col(vc) + t * other.velocities.col(vd);
      const Vec3 velocity = (1 - s) * v.col(a) + s * v.col(b);
      // The edge's point: its nodes in series.
      const double sa = (1 - s) * (1 - s), sb = s * s;
      const Unit point{1 / (sa / std::max(unit_mass(a), 1e-300) + sb / std::max(unit_mass(b), 1e-300)),
                       1 / (sa / std::max(unit_stiffness(a), 1e-300) + sb / std::max(unit_stiffness(b), 1e-300)),
                       (1 - s) * unit_size(a) + s * unit_size(b)};
      keep(contact, lambda, part_friction_, surface_velocity, velocity, dt, point);
    }
  }
}

void ContactSet::detect(const std::vector<ObstacleLink>& links, const std::vector<Pose>& poses, const Nodes& x,
                        const Nodes& v, const Vec3& gravity, double dt) {
  // The multipliers of the last step's contacts, by node, to carry over.
  previous_.swap(contacts_);
  contacts_.clear();
  const Index units = num_units(x.cols());
  if (first_contact_.value.size() != static_cast<size_t>(units)) first_contact_.value.assign(units, -1);
  for (size_t c = previous_.size(); c-- > 0;) first_contact_.value[previous_[c].node] = static_cast<int>(c);
  const auto carried = [&](Index node, int obstacle) {
    for (int c = first_contact_.value[node];
         c >= 0 && c < static_cast<int>(previous_.size()) && previous_[c].node == node; ++c)
      if (previous_[c].obstacle == obstacle && !previous_[c].edge()) return previous_[c].multiplier;
    return 0.0;
  };

  for (int j = 0; j < static_cast<int>(links.size()); ++j) {
    const Pose& end = poses[j];
    const Pose& start = links[j].seen ? links[j].last_pose : end;
    if (!table_) {
      for (Index i : nodes_)
        consider(i, x.col(i), v.col(i), *links[j].obstacle, j, start, end, links[j].friction, x, gravity, dt, carried,
                 nullptr);
      continue;
    }
    const UnitTable& table = *table_;
    const ContactPoints& points = table.points;
    const Obstacle& obstacle = *links[j].obstacle;
    for (int g = 0; g + 1 < static_cast<int>(table.group_start.size()); ++g) {
      const auto first = table.group_order.begin() + table.group_start[g];
      const auto last = table.group_order.begin() + table.group_start[g + 1];
      // A group out of the obstacle's reach is skipped, unless one of its points carried a
      // contact (which holds on where its point goes) or the surface deforms.
      const bool carries = std::any_of(first, last, [&](Index p) { return first_contact_.value[p] >= 0; });
      if (!carries && !obstacle.deforms() && group_out_of_reach(table, g, obstacle, start, end, x, v, gravity, dt))
        continue;
      for (auto it = first; it != last; ++it) {
        const Index p = *it;
        consider(p, points.of(p, x), points.of(p, v), obstacle, j, start, end, links[j].friction, x, gravity, dt,
                 carried, nullptr);
      }
    }
  }
  if (!parts_.empty()) {
    // Each part's surface where its free flight takes it, moving there with that velocity.
    for (PartSurface& part : parts_) {
      const Index count = static_cast<Index>(part.nodes.size());
      part.ends.resize(3, count);  // (sized once)
      part.velocities.resize(3, count);
      for (Index k = 0; k < count; ++k) {
        part.velocities.col(k) = v.col(part.nodes[k]) + dt * gravity;
        part.ends.col(k) = x.col(part.nodes[k]) + dt * part.velocities.col(k);
      }
      part.mesh->move_owned_vertices(part.ends, part.velocities);
      part.mean_velocity = part.velocities.rowwise().mean();
      part.spread = dt * (part.velocities.colwise() - part.mean_velocity).colwise().norm().maxCoeff();
      part.end_box = Eigen::AlignedBox3d(part.ends.rowwise().minCoeff(), part.ends.rowwise().maxCoeff());
    }
    const Pose identity;
    for (Index i : nodes_)
      for (int p = 0; p < static_cast<int>(parts_.size()); ++p)
        if (p != part_of_node_[i] &&
            !(out_of_part_reach(x.col(i), v.col(i), parts_[p], gravity, dt) && carried(i, -1 - p) == 0))
          consider(i, x.col(i), v.col(i), *parts_[p].mesh, -1 - p, identity, identity, part_friction_, x, gravity, dt,
                   carried, &parts_[p]);
    // The stamps of consider_self and consider_edges, cleared once per step (no allocation
    // after the first).
    if (has_self_contact()) neighbour_stamp_.value.assign(static_cast<size_t>(x.cols()), 0);
    if (settings_.edge_contact) edge_stamp_.value.assign(static_cast<size_t>(num_edges_), 0);
    if (has_self_contact())
      for (Index i : nodes_)
        if (vertex_of_node_[i] >= 0) consider_self(i, x, v, gravity, dt, carried);
    if (settings_.edge_contact) {
      std::vector<std::pair<Index, double>>& edge_multipliers = carried_edges_.value;
      edge_multipliers.clear();
      for (const Contact& c : previous_)
        if (c.edge() && c.multiplier > 0) edge_multipliers.emplace_back(c.edge_pair, c.multiplier);
      std::sort(edge_multipliers.begin(), edge_multipliers.end());
      std::vector<char>& touching = touching_.value;
      touching.assign(static_cast<size_t>(x.cols()), 0);
      for (const Contact& c : contacts_)
        if (c.obstacle < 0) touching[static_cast<size_t>(c.node)] = 1;
      for (PartSurface& part : parts_) {  // the triangles' normals where the step ends
        part.normals.value.resize(3, static_cast<Index>(part.triangles.size()));
        for (size_t k = 0; k < part.triangles.size(); ++k) {
          const auto& tri = part.triangles[k];
          const Vec3 e0 = part.ends.col(tri[0]);
          part.normals.value.col(static_cast<Index>(k)) =
              (part.ends.col(tri[1]) - e0).cross(part.ends.col(tri[2]) - e0).normalized();
        }
      }
      const int count = static_cast<int>(parts_.size());
      for (int p = 0; p < count; ++p)
        for (int q = has_self_contact() ? p : p + 1; q < count; ++q)
          consider_edges(p, q, x, v, gravity, dt, edge_multipliers);
    }
  }
  for (const Contact& c : previous_) first_contact_.value[c.node] = -1;  // back to all -1 (no allocation)
  share_among_points(dt);
  // Sorted by node, so that the next step finds a node's contacts side by side.
  std::sort(contacts_.begin(), contacts_.end(), [](const Contact& p, const Contact& q) {
    return p.node != q.node           ? p.node < q.node
           : p.obstacle != q.obstacle ? p.obstacle < q.obstacle
                                      : p.edge_pair < q.edge_pair;
  });
}

namespace {
// The smoothed friction's F0 and f1 = F0' and f1' (see the header), s >= 0.
double friction_potential(double s, double eps) {
  return s < eps ? s * s / eps - s * s * s / (3 * eps * eps) : s - eps / 3;
}
}  // namespace

ContactSet::Stencil ContactSet::stencil(const Contact& c) const {
  Stencil s;
  if (!table_) {
    s.nodes[0] = c.node;
    s.e[0] = c.own;
    s.size = 1;
  } else {
    const ContactPoints& points = table_->points;
    for (int k = 0; k < points.per_point; ++k) {
      s.nodes[k] = points.nodes[c.node * points.per_point + k];
      s.e[k] = points.weights[c.node * points.per_point + k];
    }
    s.size = points.per_point;
  }
  if (c.coupled())
    for (int k = 0; k < 3; ++k) {
      s.nodes[s.size] = c.partners[k];
      s.e[s.size++] = -c.weights[k];
    }
  return s;
}

Vec3 ContactSet::relative(const Contact& c, const Nodes& y) const {
  if (!table_ && !c.coupled()) return y.col(c.node);  // (the common case, without the stencil)
  const Stencil s = stencil(c);
  Vec3 r = Vec3::Zero();
  for (int a = 0; a < s.size; ++a) r += s.e[a] * y.col(s.nodes[a]);
  return r;
}

void ContactSet::add_force(const Contact& c, const Vec3& f, Nodes& out) const {
  if (!table_ && !c.coupled()) {
    out.col(c.node) += f;
    return;
  }
  const Stencil s = stencil(c);
  for (int a = 0; a < s.size; ++a) out.col(s.nodes[a]) += s.e[a] * f;
}

double ContactSet::energy_of(const Contact& c, const Vec3& r) const {
  if (!c.active) return 0;
  const double push = std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(r - c.anchor));
  double e = push * push / (2 * c.stiffness);
  if (c.friction_force > 0) {
    const Vec3 slip = r - c.slip_origin;
    const Vec3 u = slip - c.normal.dot(slip) * c.normal;
    e += c.friction_force * friction_potential(u.norm(), c.slip_width);
  }
  return e;
}

Vec3 ContactSet::normal_force(const Contact& c, const Vec3& r, Mat3* hessian) {
  const double push = std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(r - c.anchor));
  if (hessian) {
    if (push > 0) *hessian = c.stiffness * c.normal * c.normal.transpose();
    else hessian->setZero();
  }
  return push * c.normal;
}

Vec3 ContactSet::friction(const Contact& c, const Vec3& r, Mat3* hessian) {
  const Mat3 tangential = Mat3::Identity() - c.normal * c.normal.transpose();
  const Vec3 u = tangential * (r - c.slip_origin);
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

Vec3 ContactSet::force_of(const Contact& c, const Vec3& r, Mat3* hessian) const {
  if (!c.active) {
    if (hessian) hessian->setZero();
    return Vec3::Zero();
  }
  Vec3 f = normal_force(c, r, hessian);
  if (c.friction_force > 0) {
    Mat3 h;
    f += friction(c, r, hessian ? &h : nullptr);
    if (hessian) *hessian += h;
  }
  return f;
}

double ContactSet::energy(const Nodes& y) const {
  double e = 0;
  for (const Contact& c : contacts_) e += energy_of(c, relative(c, y));
  return e;
}

void ContactSet::add_forces(const Nodes& y, Nodes& f) const {
  for (const Contact& c : contacts_) add_force(c, force_of(c, relative(c, y), nullptr), f);
}

void ContactSet::add_blocks(const Contact& c, const Mat3& h, size_t k, BlockSparseMatrix* A,
                            SinglePrecisionSymmetric* single) const {
  const auto add = [&](Index node, double scale) {
    if (single) single->add_to_diagonal_block(node, scale * h);
    else A->block(A->diagonal_block(node)) += scale * h;
    diagonal_terms_.nodes.push_back(node);
    diagonal_terms_.blocks.push_back(scale * h);
  };
  if (!table_ && !c.coupled()) {
    add(c.node, 1);
    return;
  }
  const Stencil s = stencil(c);
  for (int a = 0; a < s.size; ++a) add(s.nodes[a], s.e[a] * s.e[a]);
  coupling_[k] = h;
  coupled_ = true;
}

void ContactSet::add_stiffness(const Nodes& y, double scale, BlockSparseMatrix& A) const {
  Mat3 h;
  coupling_.resize(contacts_.size());
  coupled_ = false;
  diagonal_terms_.clear();
  linearized_ = false;
  for (size_t k = 0; k < contacts_.size(); ++k) {
    const Contact& c = contacts_[k];
    force_of(c, relative(c, y), &h);
    add_blocks(c, scale * h, k, &A, nullptr);
  }
}

void ContactSet::add_linearized(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix* A,
                                SinglePrecisionSymmetric* single) const {
  Mat3 h;
  coupling_.resize(contacts_.size());
  secant_.assign(contacts_.size(), 0.0);
  coupled_ = false;
  diagonal_terms_.clear();
  linearized_ = true;
  for (size_t k = 0; k < contacts_.size(); ++k) {
    const Contact& c = contacts_[k];
    if (!c.active) continue;
    const Vec3 r = relative(c, y);
    // The normal force as the linear spring it is while the contact holds, (lambda - k g) n
    // with g = n . (r - anchor): its max(0, .) is the active set's business (update_active),
    // so a contact whose node the prediction puts outside still holds where the answer is
    // inside.
    Vec3 force = (c.multiplier - c.stiffness * c.normal.dot(r - c.anchor)) * c.normal;
    h = c.stiffness * c.normal * c.normal.transpose();
    if (c.friction_force > 0) {
      // Friction as the damping of its secant at the slip the node starts the step with:
      // force -(mu N f1(s) / s) u at the new slip u. One linear solve cannot follow the
      // smoothed law's kink (its tangent, extrapolated from a sticking slip, asks for many
      // times mu N and overshoots); the secant never exceeds mu N by more than the slip
      // grows in the step, and it only ever dissipates.
      const Mat3 tangential = Mat3::Identity() - c.normal * c.normal.transpose();
      const Vec3 u = tangential * (r - c.slip_origin);
      const double s = u.norm(), eps = c.slip_width;
      const double damping = c.friction_force * (s >= eps ? 1 / s : 2 / eps - s / (eps * eps));
      secant_[k] = damping;
      force -= damping * u;
      h += damping * tangential;
    }
    add_force(c, force, f);
    add_blocks(c, scale * h, k, A, single);
  }
}

// The coupled contacts of the last assembly (a node against a triangle of another part, or
// a contact point of several nodes): f(H, s, free) with s the stencil (r = sum_a e_a
// y_{s.nodes[a]}) and which of its nodes are free (fixed rows and columns are identity rows
// of the system: the coupling leaves them alone).
template <class F>
void ContactSet::for_each_coupled(F&& f) const {
  if (!coupled_) return;
  std::array<bool, kMaxStencil> free;
  for (size_t k = 0; k < contacts_.size(); ++k) {
    const Contact& c = contacts_[k];
    if (!c.active || (!table_ && !c.coupled())) continue;
    const Stencil s = stencil(c);
    for (int a = 0; a < s.size; ++a) free[a] = fixed_.empty() || !fixed_[static_cast<size_t>(s.nodes[a])];
    f(coupling_[k], s, free);
  }
}

void ContactSet::multiply_add(const Vec& x, Vec& y) const {
  // The off-diagonal blocks e_a e_b H (a != b) of e e^T (x) H between free nodes.
  for_each_coupled([&](const Mat3& h, const Stencil& s, const std::array<bool, kMaxStencil>& free) {
    Vec3 sum = Vec3::Zero();
    for (int a = 0; a < s.size; ++a)
      if (free[a]) sum += s.e[a] * x.segment<3>(3 * s.nodes[a]);
    const Vec3 hs = h * sum;
    for (int a = 0; a < s.size; ++a)
      if (free[a]) y.segment<3>(3 * s.nodes[a]) += s.e[a] * (hs - s.e[a] * (h * x.segment<3>(3 * s.nodes[a])));
  });
}

void ContactSet::for_each_block(const std::function<void(Index, Index, const Mat3&)>& visit) const {
  for_each_coupled([&](const Mat3& h, const Stencil& s, const std::array<bool, kMaxStencil>& free) {
    for (int a = 0; a < s.size; ++a)
      for (int b = 0; b < s.size; ++b)
        if (a != b && free[a] && free[b]) visit(s.nodes[a], s.nodes[b], s.e[a] * s.e[b] * h);
  });
}

void ContactSet::activate_all() {
  for (Contact& c : contacts_) c.active = true;
}

bool ContactSet::has_impacts() const {
  for (const Contact& c : contacts_)
    if (c.impact) return true;
  return false;
}

bool ContactSet::update_active(const Nodes& x_new) {
  bool changed = false;
  for (Contact& c : contacts_) {
    const double gap = c.normal.dot(relative(c, x_new) - c.anchor);
    // Released where its linear force pulls (gap > lambda / k) and the node, let go, would
    // end clearly off the plane: a contact resting on the surface ends within an inexact
    // solve's noise of it, where the sign of its force would flip from pass to pass (and every
    // flip costs a pass with an accurate solve). "Clearly" is 1e-3 of the node's size on a
    // surface at rest, and 1e-6 on a moving one (solved accurately anyway, has_impacts): there
    // a band of 1e-3 held the tissue a tool moved away from. (1e-6 at impacts too cost the
    // landing armadillo five times the CG iterations, in passes.)
    //
    // "Let go": held by a contact stiffness_scale times stiffer than the node itself is in the
    // step, a node ends barely off the plane even when the contact pulls hard. Tested on its
    // gap alone, a body thrown off the floor stayed on it (each contact pulling with up to k
    // times the band, hundreds of times its node's weight). Let go, the node moves on by its
    // pull over its own stiffness, k / stiffness_scale, to gap + stiffness_scale (gap - lambda / k).
    const double noise = (c.moving_surface ? 1e-6 : 1e-3) * c.size;
    const double carried = c.multiplier / c.stiffness, scale = settings_.stiffness_scale;
    const double band = std::max(carried, (noise + scale * carried) / (1 + scale));
    const bool active = c.active ? gap <= band : gap < -noise;
    changed = changed || active != c.active;
    c.active = active;
  }
  return changed;
}

void ContactSet::commit(const Nodes& x_new) {
  forces_.resize(3, static_cast<Index>(contacts_.size()));
  for (size_t k = 0; k < contacts_.size(); ++k) {
    Contact& c = contacts_[k];
    const Vec3 r = relative(c, x_new);
    if (linearized_ && c.active) {
      // What the linearised step applied: the linear spring (a pull too, within the active
      // set's band) and friction's secant damping. Reported as applied, the contact forces
      // and the momentum the body gained agree.
      const Vec3 slip = r - c.slip_origin;
      forces_.col(static_cast<Index>(k)) = (c.multiplier - c.stiffness * c.normal.dot(r - c.anchor)) * c.normal -
                                           secant_[k] * (slip - c.normal.dot(slip) * c.normal);
    } else {
      forces_.col(static_cast<Index>(k)) = force_of(c, r, nullptr);
    }
    c.multiplier = c.active ? std::max(0.0, c.multiplier - c.stiffness * c.normal.dot(r - c.anchor)) : 0.0;
  }
}

void ContactSet::reset() {
  contacts_.clear();
  previous_.clear();
  forces_.resize(3, 0);
}

}  // namespace corotate
