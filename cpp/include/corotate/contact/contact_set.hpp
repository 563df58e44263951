// Contact of one body with rigid obstacles, inside the implicit step.
//
// Detection (once per step, detect()): each contact node's path over the step, from x to the
// free-flight prediction x + dt v + dt^2 g, is marched against every obstacle in the
// obstacle's moving frame (from the pose this body last saw it at to its current one). The
// march advances by the signed distance, which no surface can be nearer than, so a node that
// would cross a thin obstacle within the step is caught where it first touches: no
// tunnelling at any speed. A touching node gets the obstacle's tangent plane there (point p,
// outward normal n, both at the obstacle's current pose): its gap is g(y) = n . (y - p).
//
// The contact potential of node i against its plane, with stiffness k and multiplier lambda,
//     E_n = (1 / 2k) max(0, lambda - k g)^2,  force max(0, lambda - k g) n,  Hessian k n n^T
// (an augmented Lagrangian: after each step lambda <- max(0, lambda - k g(x_new)), the force
// the contact carried, so a resting contact's gap goes to zero over steps while k stays
// moderate). k = stiffness_scale * (m_i / dt^2 + k_i), with m_i the node's lumped mass and
// k_i its share of the body's rest stiffness (trace / 3 of the diagonal block): the contact
// is stiffness_scale times stiffer than the node itself is in the step's system.
//
// Coulomb friction, lagged (IPC's smoothed friction, Li et al. 2020): with the normal force N
// the contact carried into the step (lambda) and the slip u = P_t (y - x - dt v_obstacle),
// P_t = I - n n^T,
//     E_t = mu N F0(|u|),  force -mu N f1(|u|) u / |u|,
// f1(s) = 2 s / eps - s^2 / eps^2 below eps and 1 above, eps = max(friction_velocity * dt,
// mu N / k): a block below the friction cone creeps at less than friction_velocity (or by
// the normal contact's own compliance per step); above, it slides with the force mu N
// exactly. Both potentials are C1 with positive semi-definite Hessians, so the
// Newton integrator minimises them with the body's incremental potential and the linearised
// one evaluates them at y = x + dt v like the body's forces.
//
// Parts of one body (its mesh's separate pieces: several bodies simulated together) touch
// each other the same way: a node of one part against the closed surface of another, taken
// where the part's own free flight puts it at the step's end (the part's surface is a
// TriangleMesh whose vertices move). The contact point then moves with the triangle it lies
// on: with barycentric weights w_j of the triangle's corners, the gap is
// g(y) = n . (y_i - sum_j w_j y_j), and every potential above is a function of the relative
// position r = y_i - sum_j w_j y_j (friction of its slip: r - r at the step's start). The
// force on the node is f, on the corners -w_j f (equal and opposite: momentum is kept), and
// the Hessian is e e^T (x) H with e = (1, -w_1, -w_2, -w_3): its diagonal blocks go into the
// system matrix, its coupling blocks (between nodes that share no element) into the solve as
// a SystemCoupling (solvers/linear_solver.hpp), not into the sparse pattern.
//
// Self-contact (an option): a part's surface nodes also touch the part's own surface, away
// from their neighbourhood (triangles with a corner that shares an element with the node are
// left out: the node lies on or next to them). A node's path over the step, taken relative to
// a triangle (the node's start moved by the triangle's own motion over the step, the triangle
// where its free flight ends), that crosses the triangle from its front to its back is a
// contact where it crosses, as is a path that ends in front of it by less than half its
// length plus dt^2 g (free flight is only a prediction: a resting surface does not fall by
// dt^2 g), or a node that starts less than a quarter of its size behind a triangle it
// projects onto; only surfaces that face each other count (the node's own normal against
// the triangle's). The contact is then a part's contact like any other:
// the gap n . (y_i - sum_j w_j y_j) along the triangle's normal.
//
// Edge against edge (an option, on by default, between parts and, with self-contact, within
// one): two surfaces' edges can cross with no node inside the other surface (two ridges
// crossed like the beams of a cross, a box's edge across another's). A convex edge (a, b) of
// one surface and a convex edge (c, d) of another (or of the same part, away from their
// neighbourhoods) whose nearest points at the step's predicted end, p(s) = a + s (b - a) and
// q(t) = c + t (d - c), lie inside both edges (more than 2 % from their ends, where a node's
// own contact holds them) touch along their common normal n = (b - a) x (d - c) / |...|,
// turned out of the second surface, when n lies in the second edge's normal cone and -n in
// the first's (each edge is then the other surface's nearest feature; with 6 degrees of
// slack, as a face's rim across a ridge puts n on the border) and the pair ends crossed or in
// front by less than half its relative path plus dt^2 g, having started at most a quarter of
// its size behind. Where a node of either edge already touches a part, its contact holds the
// pair (a face resting on a face: the rims cross at one height). The contact is a part's
// contact of the relative position r = (1 - s) y_a + s y_b - (1 - t) y_c - t y_d along n,
// with e = (1 - s, s, -(1 - t), -t): everything above holds for it, its mass and stiffness
// those of the edge's nodes in series. A pair that ends in front starts released, for the
// active set to take in.
//
// Contact points other than the nodes (an option, against obstacles): the vertices of an
// embedded render surface, so that the detailed surface, not the coarse body, touches the
// world. Point p is a fixed combination sum_k w_k x_{n_k} of one element's nodes (its
// shape-function weights); it is detected and held like a node, and every potential above is
// a function of its position, so its force f spreads as w_k f over the nodes and its Hessian
// H as w_a w_b H over their pairs (in the element's blocks: the coupling's, as between
// parts). In the contact stiffness the point's mass and stiffness are the nodes' in series,
// each node shared among the step's contact points that use it: 1 / sum_k (w_k^2 L_k / m_k)
// and 1 / sum_k (w_k^2 L_k / k_k), with node k's load L_k = sum_p w_pk^2 over the step's
// contacts. A point at a node that no other contact uses gets the node's own; a fine
// surface's many points on one coarse element add up to about what its nodes would have alone
// (without the shares, 12,000 render vertices on Table 1's 653-tet cage made the landing's
// system so stiff that its capped solve inverted elements; shared among all the surface's
// points, not the step's contacts, a foot landing on a few points sank 1 mm).
//
// Only diagonal blocks of the system's pattern change: contact rebuilds no pattern,
// factorization or preconditioner hierarchy.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "corotate/contact/obstacle.hpp"
#include "corotate/contact/surface_edges.hpp"
#include "corotate/contact/triangle_mesh.hpp"
#include "corotate/solvers/linear_solver.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class SinglePrecisionSymmetric;

struct ContactSettings {
  double stiffness_scale = 100;     // contact stiffness / the node's own stiffness in the step
  double friction_velocity = 1e-3;  // [m/s] slip speed below which friction sticks (smoothed)
  bool edge_contact = true;         // edges against edges between parts (and within one)
  void validate() const;            // throws InvalidInput naming the parameter
};

// An obstacle as one body sees it: the obstacle, its friction coefficient against this body
// and the pose at which this body last stepped with it (where its motion over the next step
// starts).
struct ObstacleLink {
  std::shared_ptr<Obstacle> obstacle;
  double friction = 0;
  Pose last_pose;
  bool seen = false;  // last_pose valid (no motion is assumed over the first step)
};

// Work space that a copy of its owner does not copy (the copy makes its own when it needs
// it): a step's backup of the contact set copies the set at every step.
template <class T>
struct Scratch {
  T value;
  Scratch() = default;
  Scratch(const Scratch&) {}
  Scratch& operator=(const Scratch&) { return *this; }
};

// The closed surface of one part of the body, as the other parts see it.
struct PartSurface {
  // Vertices: the part's surface nodes, in this order. Private to the simulation, which moves
  // it in place each step (TriangleMesh::move_owned_vertices; a failed step's backup of the
  // contact set shares it, as the next step moves it again from the nodes).
  std::shared_ptr<TriangleMesh> mesh;
  std::vector<Index> nodes;  // mesh vertex -> body node
  Triangles triangles;       // the mesh's outward triangles (vertex indices)
  std::shared_ptr<const SurfaceEdges> edges;  // theirs (set_parts builds them)
  Nodes ends, velocities;    // the step's predicted vertices and their velocities (work space)
  Vec3 mean_velocity = Vec3::Zero();  // of the vertices over the step, and dt times the
  double spread = 0;                  // largest speed relative to it (self-contact's reach)
  Scratch<Nodes> normals;             // the triangles' unit normals at ends (edge contact)
  Eigen::AlignedBox3d end_box;        // of the vertices at ends
};

// Contact points other than the nodes (see above): per_point nodes and weights per point.
struct ContactPoints {
  int per_point = 0;
  std::vector<Index> nodes;
  std::vector<double> weights;
  Index size() const { return per_point > 0 ? static_cast<Index>(nodes.size()) / per_point : 0; }
  bool empty() const { return per_point == 0; }
  // Point p of nodal values y (3 x n): positions or velocities.
  Vec3 of(Index p, const Nodes& y) const {
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < per_point; ++k) sum += weights[p * per_point + k] * y.col(nodes[p * per_point + k]);
    return sum;
  }
};

// One active contact of the step.
struct Contact {
  Index node = 0;  // its contact node, or with contact points (set_points) the point; an
                   // edge's first node
  double own = 1;  // node's coefficient in r (1, or an edge's point: 1 - s)
  Index edge_pair = -1;  // an edge against an edge: the pair's key (its multiplier's, step to step)
  int obstacle = 0;           // index into the links; -1 - p for part p of the body
  std::array<Index, 3> partners = {-1, -1, -1};  // a part's triangle: its corner nodes
  Vec3 weights = Vec3::Zero();                   // and the contact point's weights on them
  Vec3 normal, point;         // the tangent plane at the obstacle's current pose
  Vec3 anchor;                // gap = n . (r - anchor): the point (obstacle), 0 (part)
  Vec3 slip_origin;           // r of a node that sticks at the step's end: x + dt v_obstacle
  double stiffness = 0;       // k [N/m]
  double multiplier = 0;      // lambda [N]
  double friction_force = 0;  // mu N, N lagged: the multiplier carried into the step [N]
  double slip_width = 0;      // eps [m] of the smoothed friction
  double size = 0;            // its node's (point's, edge point's) size [m]
  bool active = true;         // false: released by the linearised step (update_active), or
                              // a self-contact's path that ends just in front (taken in there)
  bool impact = false;        // new and closing fast, or on a moving surface (has_impacts)
  bool moving_surface = false;  // the surface moves by 1 % of the node's size in the step
  bool coupled() const { return partners[0] >= 0; }
  bool edge() const { return edge_pair >= 0; }
};

class ContactSet final : public SystemCoupling {
 public:
  // Per node of the body: its lumped mass, rest stiffness (k_i above) and size (the mean
  // rest distance to the nodes it shares elements with).
  void set_node_properties(Vec masses, Vec node_stiffness, Vec node_sizes);
  bool has_node_properties() const { return nodes_table_ != nullptr; }

  bool empty() const { return contacts_.empty(); }
  const std::vector<Contact>& contacts() const { return contacts_; }
  const std::vector<Index>& nodes() const { return nodes_; }
  // The nodes that can touch (the body's surface; validated by the caller).
  void set_nodes(std::vector<Index> nodes);
  // Contact points instead of the nodes (validated by the caller, after the node properties;
  // empty: back to the nodes). Not with contact between parts.
  void set_points(ContactPoints points);
  const ContactPoints& points() const { return table_ ? table_->points : kNoPoints; }
  // How many contact units (nodes of the body, or points) and their positions at x (3 x n).
  Index num_units(Index num_nodes) const { return table_ ? table_->points.size() : num_nodes; }
  Nodes unit_positions(const Nodes& x) const;
  // The units that can touch: the contact nodes, or every point.
  template <class F>
  void for_each_unit(F&& f) const {
    if (!table_)
      for (Index i : nodes_) f(i);
    else
      for (Index p = 0; p < table_->points.size(); ++p) f(p);
  }
  void set_settings(const ContactSettings& settings);
  const ContactSettings& settings() const { return settings_; }

  // Contact between the body's parts: part_of_node (one id per node, 0..P-1) and each
  // part's closed surface; friction between any two parts. Empty parts: none. With
  // neighbourhoods (the body's pattern: block (i, j) when nodes i and j share an element;
  // the caller keeps it alive), self-contact within each part too, away from them.
  void set_parts(std::vector<int> part_of_node, std::vector<PartSurface> parts, double friction,
                 const BlockSparseMatrix* neighbourhoods = nullptr);
  bool has_parts() const { return !parts_.empty(); }
  bool has_self_contact() const { return neighbourhoods_ != nullptr; }
  const std::vector<PartSurface>& parts() const { return parts_; }
  const std::vector<int>& part_of_node() const { return part_of_node_; }
  double part_friction() const { return part_friction_; }
  // The fixed nodes: the coupling leaves their rows and columns alone (they are identity
  // rows of the system).
  void set_fixed_nodes(Index num_nodes, const std::vector<Index>& fixed);

  // The step's contacts from the state at its start (see above); poses: each link's current
  // pose, read once.
  void detect(const std::vector<ObstacleLink>& links, const std::vector<Pose>& poses, const Nodes& x, const Nodes& v,
              const Vec3& gravity, double dt);

  // The potentials at positions y (3 x n), as Attachments has them.
  double energy(const Nodes& y) const;
  void add_forces(const Nodes& y, Nodes& f) const;
  void add_stiffness(const Nodes& y, double scale, BlockSparseMatrix& A) const;
  // For the linearised step: each active contact's normal force as the linear spring
  // (lambda - k g(y)) n, A += scale k n n^T, whatever the sign (the active set, update_active,
  // releases contacts that pull); friction as the damping of its secant at the slip of y
  // (see the source for why not its tangent).
  void add_linearized(const Nodes& y, Nodes& f, double scale, BlockSparseMatrix* A,
                      SinglePrecisionSymmetric* single) const;

  // For the linearised step's active set: releases the active contacts whose linear force
  // at x_new pulls (a tool lifted away, a landing node whose path crossed the floor too), and
  // takes back released ones whose node ended inside; returns whether any changed. Both only
  // beyond 1e-3 of the node's size (1e-6 on a moving surface, solved accurately): a node
  // that rests on or touches a surface ends within an inexact solve's noise of it, and would
  // flip from pass to pass. A pulled node is judged where it would end let go (its gap plus
  // its pull over its own stiffness), not where the stiff contact held it.
  bool update_active(const Nodes& x_new);
  // Makes every contact active (the Newton step: its potentials' max(0, .) is its own
  // active set).
  void activate_all();
  // Whether a contact new in this step (no force carried) closes at more than 1 % of its
  // node's size per step relative to the obstacle (an impact, a tool pushed in fast), or
  // any contact with a surface that moves by as much: the step then needs an accurate solve.
  bool has_impacts() const;

  // After a step ending at x_new: the multipliers for the next step, and the force each
  // contact exerted on the body in the step (normal and friction), per contact: the
  // potentials' forces at x_new after a Newton step, what the linearised step applied after
  // one (its linear springs and friction's secant).
  void commit(const Nodes& x_new);
  const Nodes& forces() const { return forces_; }  // 3 x contacts(), at the last commit

  // Multipliers by (node, obstacle) carried from step to step; cleared by reset().
  void reset();

  // One contact's potential, force on its node and Hessian (optional) at the relative
  // position r (the node's position for an obstacle; see relative()).
  double energy_of(const Contact& c, const Vec3& r) const;
  Vec3 force_of(const Contact& c, const Vec3& r, Mat3* hessian) const;
  // r = y_i - sum_j w_j y_j (y_i for an obstacle's contact; y_i the point's position for a
  // contact point).
  Vec3 relative(const Contact& c, const Nodes& y) const;
  // The nodes r combines and their coefficients e: r = sum_a e_a y_{nodes[a]}.
  static constexpr int kMaxStencil = 24;  // a Hex20 point (20 nodes) and a triangle (3)
  struct Stencil {
    std::array<Index, kMaxStencil> nodes;
    std::array<double, kMaxStencil> e;
    int size = 0;
  };
  Stencil stencil(const Contact& c) const;

  // Whether this step's contacts have blocks between nodes (contacts between parts, or
  // contact points of several nodes), which the solve needs as the coupling (set by
  // add_stiffness and add_linearized: the blocks of the last one called).
  bool has_coupling() const { return coupled_; }
  // The diagonal blocks the last add_stiffness / add_linearized added (scaled), for a
  // solver's coarse level (solvers/diagonal_terms.hpp).
  const DiagonalTerms& diagonal_terms() const { return diagonal_terms_; }
  // y += C x: the Hessian's blocks between a node and the corners it touches, and between
  // the corners (scaled as in the last add_stiffness / add_linearized).
  void multiply_add(const Vec& x, Vec& y) const override;
  void for_each_block(const std::function<void(Index, Index, const Mat3&)>& visit) const override;

 private:
  // The two parts of force_of (the Hessian, when asked, is set, not added).
  static Vec3 normal_force(const Contact& c, const Vec3& y, Mat3* hessian);
  static Vec3 friction(const Contact& c, const Vec3& y, Mat3* hessian);

  // Adds e_a e_b H to the diagonal blocks of A (or single) for the contact's nodes, and
  // keeps H for the coupling.
  void add_blocks(const Contact& c, const Mat3& h, size_t k, BlockSparseMatrix* A,
                  SinglePrecisionSymmetric* single) const;
  // f(H, stencil, free) for each contact with blocks between nodes (see the source).
  template <class F>
  void for_each_coupled(F&& f) const;
  // The forces e_a f on the stencil's nodes (f on the node, -w_j f on the corners).
  void add_force(const Contact& c, const Vec3& f, Nodes& out) const;
  // The unit's mass, rest stiffness and size (the node's, or the point's: see above).
  double unit_mass(Index i) const { return (table_ ? *table_ : *nodes_table_).masses[i]; }
  double unit_stiffness(Index i) const { return (table_ ? *table_ : *nodes_table_).stiffness[i]; }
  double unit_size(Index i) const { return (table_ ? *table_ : *nodes_table_).sizes[i]; }
  // A unit's mass, rest stiffness and size, for keep().
  struct Unit {
    double mass, stiffness, size;
  };
  Unit unit(Index i) const { return {unit_mass(i), unit_stiffness(i), unit_size(i)}; }
  // One contact of node i against a surface, if its path touches it (detect()).
  template <class Carried>
  void consider(Index i, const Vec3& xi, const Vec3& vi, const Obstacle& surface, int id, const Pose& start,
                const Pose& end, double friction, const Nodes& x, const Vec3& gravity, double dt,
                const Carried& carried, const PartSurface* part);
  // The edges of part p against those of part q (q > p; q == p: self-contact, away from
  // each edge's neighbourhood), where they cross or are about to (see above). `carried`: the
  // last step's edge contacts' multipliers by key, sorted.
  void consider_edges(int p, int q, const Nodes& x, const Nodes& v, const Vec3& gravity, double dt,
                      const std::vector<std::pair<Index, double>>& carried);
  // Node i (on its part's surface) against that surface, away from its neighbourhood.
  template <class Carried>
  void consider_self(Index i, const Nodes& x, const Nodes& v, const Vec3& gravity, double dt, const Carried& carried);
  // Contact points: each contact's stiffness from its nodes shared among the step's contacts
  // (see above).
  void share_among_points(double dt);
  // Sets c's stiffness, multiplier, friction and impact flags and keeps it: c touches a
  // surface moving at surface_velocity, having carried lambda.
  void keep(Contact& c, double lambda, double friction, const Vec3& surface_velocity, const Vec3& vi, double dt,
            const Unit& unit);

  std::vector<Index> nodes_;
  std::vector<int> part_of_node_;
  std::vector<int> vertex_of_node_;  // a node's vertex on its part's surface (-1: none)
  std::vector<PartSurface> parts_;
  double part_friction_ = 0;
  const BlockSparseMatrix* neighbourhoods_ = nullptr;  // the model's pattern; null: no self-contact
  Scratch<std::vector<int>> candidates_;                    // self-contact's range query
  Scratch<std::vector<int>> candidate_edges_;               // edge contact's
  // Per node and per edge (of all parts): the last node (its index + 1, consider_self) or
  // edge (minus its index among all parts' edges + 1, consider_edges) whose neighbourhood
  // holds the node, and the last edge that listed the edge as a candidate: O(1) tests instead
  // of a search of the pattern per pair and a sort per edge. Cleared once per step (detect).
  Scratch<std::vector<int>> neighbour_stamp_, edge_stamp_;
  Scratch<std::vector<char>> touching_;                     // per node: in a part's contact
  Scratch<std::vector<std::pair<Index, double>>> carried_edges_;  // (key, multiplier), sorted
  std::vector<Index> edge_offset_;                          // part p's first edge's key
  Index num_edges_ = 0;                                     // of all parts
  std::vector<char> fixed_;                 // per node
  mutable std::vector<Mat3> coupling_;      // per contact: H of the last assembly (scaled)
  mutable bool coupled_ = false;
  mutable DiagonalTerms diagonal_terms_;    // the diagonal blocks of the last assembly
  mutable std::vector<double> secant_;      // per contact: friction's secant damping (add_linearized)
  mutable bool linearized_ = false;         // the last assembly was add_linearized's
  // The nodes' masses, rest stiffnesses and sizes; the contact points (null: the nodes are)
  // and theirs.
  struct UnitTable {
    ContactPoints points;
    Vec masses, stiffness, sizes;
    // The points grouped by their nodes (one group per element that carries points): group g
    // is points order[start[g], start[g + 1]), each a combination of the same nodes with
    // sum_k |w_k| <= spread[g]. Detection skips a group that no obstacle can reach.
    std::vector<int> group_start;
    std::vector<Index> group_order;
    std::vector<double> group_spread;
  };
  // Whether detection can skip group g against a rigid obstacle (see detect()).
  bool group_out_of_reach(const UnitTable& table, int g, const Obstacle& obstacle, const Pose& start, const Pose& end,
                          const Nodes& x, const Nodes& v, const Vec3& gravity, double dt) const;
  std::shared_ptr<const UnitTable> nodes_table_, table_;
  static const ContactPoints kNoPoints;
  ContactSettings settings_;
  std::vector<Contact> contacts_, previous_;  // this step's; the last step's (detect())
  Scratch<std::vector<int>> first_contact_;
  Scratch<std::vector<double>>
      load_;  // per node (share_among_points)  // per unit: its first contact in previous_, or -1
  Nodes forces_;
};

}  // namespace corotate
