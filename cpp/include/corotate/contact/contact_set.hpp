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
// Only diagonal blocks of the system's pattern change: contact rebuilds no pattern,
// factorization or preconditioner hierarchy.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "corotate/contact/obstacle.hpp"
#include "corotate/contact/triangle_mesh.hpp"
#include "corotate/solvers/linear_solver.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class SinglePrecisionSymmetric;

struct ContactSettings {
  double stiffness_scale = 100;     // contact stiffness / the node's own stiffness in the step
  double friction_velocity = 1e-3;  // [m/s] slip speed below which friction sticks (smoothed)
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

// The closed surface of one part of the body, as the other parts see it.
struct PartSurface {
  // Vertices: the part's surface nodes, in this order. Private to the simulation, which moves
  // it in place each step (TriangleMesh::move_owned_vertices; a failed step's backup of the
  // contact set shares it, as the next step moves it again from the nodes).
  std::shared_ptr<TriangleMesh> mesh;
  std::vector<Index> nodes;  // mesh vertex -> body node
  Triangles triangles;       // the mesh's outward triangles (vertex indices)
  Nodes ends, velocities;    // the step's predicted vertices and their velocities (work space)
  Vec3 mean_velocity = Vec3::Zero();  // of the vertices over the step, and dt times the
  double spread = 0;                  // largest speed relative to it (self-contact's reach)
};

// The nodes that share an element with each node (itself included), for self-contact's
// exclusion of a node's own neighbourhood: row i is nodes[start[i], start[i + 1]), sorted.
struct NodeNeighbours {
  std::vector<int> start;
  std::vector<Index> nodes;
  bool empty() const { return start.empty(); }
  bool contains(Index i, Index j) const;
};

// One active contact of the step.
struct Contact {
  Index node = 0;
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
  bool active = true;         // false: released by the linearised step (update_active), or
                              // a self-contact's path that ends just in front (taken in there)
  bool impact = false;        // new and closing fast, or on a moving surface (has_impacts)
  bool moving_surface = false;  // the surface moves by 1 % of the node's size in the step
  bool coupled() const { return partners[0] >= 0; }
};

class ContactSet final : public SystemCoupling {
 public:
  // Per node of the body: its lumped mass, rest stiffness (k_i above) and size (the mean
  // rest distance to the nodes it shares elements with).
  void set_node_properties(Vec masses, Vec node_stiffness, Vec node_sizes);
  bool has_node_properties() const { return masses_.size() > 0; }

  bool empty() const { return contacts_.empty(); }
  const std::vector<Contact>& contacts() const { return contacts_; }
  const std::vector<Index>& nodes() const { return nodes_; }
  // The nodes that can touch (the body's surface; validated by the caller).
  void set_nodes(std::vector<Index> nodes);
  void set_settings(const ContactSettings& settings);
  const ContactSettings& settings() const { return settings_; }

  // Contact between the body's parts: part_of_node (one id per node, 0..P-1) and each
  // part's closed surface; friction between any two parts. Empty parts: none. Non-empty
  // self_neighbours: self-contact within each part too, away from these neighbourhoods.
  void set_parts(std::vector<int> part_of_node, std::vector<PartSurface> parts, double friction,
                 NodeNeighbours self_neighbours = {});
  bool has_parts() const { return !parts_.empty(); }
  bool has_self_contact() const { return !self_neighbours_.empty(); }
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
  // flip from pass to pass.
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
  // r = y_i - sum_j w_j y_j (y_i for an obstacle's contact).
  static Vec3 relative(const Contact& c, const Nodes& y);

  // Whether this step has contacts between parts, whose coupling blocks the solve needs
  // (set by add_stiffness and add_linearized: the blocks of the last one called).
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
  template <class F>
  void for_each_coupled(F&& f) const;
  // The forces f on the node and -w_j f on the corners.
  static void add_force(const Contact& c, const Vec3& f, Nodes& out);
  // One contact of node i against a surface, if its path touches it (detect()).
  template <class Carried>
  void consider(Index i, const Obstacle& surface, int id, const Pose& start, const Pose& end, double friction,
                const Nodes& x, const Nodes& v, const Vec3& gravity, double dt, const Carried& carried,
                const PartSurface* part);
  // Node i (on its part's surface) against that surface, away from its neighbourhood.
  template <class Carried>
  void consider_self(Index i, const Nodes& x, const Nodes& v, const Vec3& gravity, double dt, const Carried& carried);
  // Sets c's stiffness, multiplier, friction and impact flags and keeps it: c touches a
  // surface moving at surface_velocity, having carried lambda.
  void keep(Contact& c, double lambda, double friction, const Vec3& surface_velocity, const Nodes& v, double dt);

  std::vector<Index> nodes_;
  std::vector<int> part_of_node_;
  std::vector<int> vertex_of_node_;  // a node's vertex on its part's surface (-1: none)
  std::vector<PartSurface> parts_;
  double part_friction_ = 0;
  NodeNeighbours self_neighbours_;           // empty: no self-contact
  std::vector<int> candidates_;              // self-contact's range query (work space)
  std::vector<char> fixed_;                 // per node
  mutable std::vector<Mat3> coupling_;      // per contact: H of the last assembly (scaled)
  mutable bool coupled_ = false;
  mutable DiagonalTerms diagonal_terms_;    // the diagonal blocks of the last assembly
  mutable std::vector<double> secant_;      // per contact: friction's secant damping (add_linearized)
  mutable bool linearized_ = false;         // the last assembly was add_linearized's
  Vec masses_, node_stiffness_, node_sizes_;
  ContactSettings settings_;
  std::vector<Contact> contacts_, previous_;  // this step's; the last step's (detect())
  std::vector<int> first_contact_;             // per node: its first contact in previous_, or -1
  Nodes forces_;
};

}  // namespace corotate
