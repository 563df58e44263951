// The interface every force model provides; integrators, solvers and the static solver
// depend on this only, never on a concrete model.
//
// One entry point, evaluate(x, what, out): everything it returns depends on its arguments
// only, so there is no call order to remember. Models may cache things that only make the
// next call faster (warm starts of the rotation extraction), never things that change its
// answer.
//
// Stiffness kinds (K = -df/dx means the Hessian of the energy where there is one):
//   Model      the stiffness implicit steps assemble: R K_e R^T for the co-rotational model
//              (the paper's eq. 4, leaving out dR/dx), the exact Hessian for the
//              hyperelastic and spring models (projected to PSD per element if asked).
//   Tangent    the exact derivative -df/dx, for Newton solves that want quadratic
//              convergence; equals Model except for co-rotated elements (rotation terms
//              included). Where the exact tangent is undefined (an inverted co-rotated
//              element) the element falls back to its Model stiffness. Not symmetric where
//              the forces are not the gradient of an energy (co-rotated hexes): then
//              symmetric_tangent() is false and all blocks of the matrix are filled.
//   Geometric  the initial-stress stiffness K_sigma of K_T = K_0 + K_u + K_sigma (paper
//              eq. 6): blocks sum_q w_q (G_a^T S G_b) I_3, S the second Piola-Kirchhoff
//              stress at x. Only models with a stress measure for it (hyperelastic);
//              others throw InvalidInput.
#pragma once

#include <Eigen/Geometry>
#include <memory>

#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

class ExplicitTraits;
class SinglePrecisionSymmetric;

enum class StiffnessKind { None, Model, Tangent, Geometric };

// What evaluate() computes.
struct Request {
  bool energy = false;
  bool forces = false;
  StiffnessKind stiffness = StiffnessKind::None;
  double stiffness_scale = 1.0;  // A += scale * K
  // When set, the forces are the force linearised about x, evaluated at y = *forces_at:
  //     f(x) - K(x) (y - x)   with K the Model stiffness.
  // For the co-rotational model that is the force formula at y with the rotations of x, so
  // an implicit step gets its -K v term without a matrix-vector product. Needs stiffness
  // None or Model.
  const Nodes* forces_at = nullptr;
  // Count the elements that are inverted or flat at x (det F <= 0 at the centre, or at a
  // quadrature point): what a simulation reports as a loud failure. Models without a
  // deformation gradient (linear, springs) count none.
  bool count_inverted = false;
  // False: the stiffness may leave stale the blocks below the diagonal that
  // BlockSparseMatrix::multiply_symmetric never reads (is_product_block false), for a solve
  // that reads no others (LinearSolver::needs_lower_blocks): a third fewer blocks to add.
  bool lower_blocks = true;
  // Where the model measures_frame_drift: the largest angle any element frame turned since
  // the last sweep that assembled the Model stiffness with this flag goes to
  // Results::frame_drift, and with the Model stiffness this sweep's frames become the ones
  // measured from. What lets the linearised step keep its matrix while the body turns
  // little (kept_system.hpp).
  bool frame_drift = false;
  // With frame_drift, when set: the recorded frames are measured from as turned since by
  // frame_turn[frame_turn_of_node[i]] (i an element's first node): how far the elements
  // turned beyond the rotation of their part of the body (kept_system.hpp).
  const Eigen::Quaterniond* frame_turn = nullptr;
  const int* frame_turn_of_node = nullptr;
};

// Where evaluate() puts it. Forces and stiffness are added to what is there.
struct Results {
  double energy = 0;                       // set (not added) when requested
  Nodes* forces = nullptr;                 // 3 x n, += internal forces
  BlockSparseMatrix* stiffness = nullptr;  // in pattern(), += scale * K
  // Instead of stiffness, where the model can (assembles_single_precision): the Model
  // stiffness added straight into this float32 system in its own layout and scale (built
  // for pattern()), the blocks its product reads only. The implicit step's fast path.
  SinglePrecisionSymmetric* single_stiffness = nullptr;
  Index inverted = 0;  // set when count_inverted was requested
  // Set when frame_drift was requested: the largest rotation [rad] of an element frame since
  // the last sweep that assembled with frame_drift (infinity if none).
  double frame_drift = 0;
};

class ForceModel {
 public:
  virtual ~ForceModel() = default;

  virtual const char* name() const = 0;
  // An independent copy (a simulation steps its own copy of a body's model).
  virtual std::unique_ptr<ForceModel> clone() const = 0;
  virtual Index num_nodes() const = 0;
  virtual const Nodes& rest_positions() const = 0;
  // Sparsity of the stiffness (and mass) matrices; fixed for the life of the model.
  virtual const BlockSparseMatrix& pattern() const = 0;
  // Mass matrix in pattern(): consistent, or lumped (diagonal blocks only).
  virtual BlockSparseMatrix mass_matrix(bool lumped) const = 0;
  // True when forces are linear in x (a static solve is then a single linear solve).
  virtual bool is_linear() const = 0;
  // False when the Tangent stiffness is not symmetric (solve it with a non-symmetric solver).
  virtual bool symmetric_tangent() const { return true; }
  // Whether evaluate() can add the Model stiffness, with forces, to Results::single_stiffness.
  virtual bool assembles_single_precision() const { return false; }
  // Whether the stiffness depends on the configuration only through element frames that
  // evaluate() can compare with those of the last assembly (Request::frame_drift): the
  // co-rotated tets (their K is R K0 R^T) and the constant-stiffness models (drift 0).
  virtual bool measures_frame_drift() const { return false; }
  // Whether the stiffness turns with the body (K(R x) = R K(x) R^T for a rigid rotation R:
  // the co-rotated models), rather than staying as it is (the linear model).
  virtual bool stiffness_turns() const { return false; }

  // Energy, forces and/or stiffness at positions x (3 x n), as `what` asks. Throws
  // InvalidInput for a request the model cannot answer (Geometric on a model without a
  // stress measure, mismatched sizes).
  virtual void evaluate(const Nodes& x, const Request& what, Results& out) = 0;

  // What explicit integration asks beyond evaluate() (the model's own velocity damping and
  // configuration-independent bounds); nullptr for models that have none.
  virtual const ExplicitTraits* explicit_traits() const { return nullptr; }

  // Caches that speed up evaluate() (warm starts of the rotation extraction) change its
  // answers at the level of round-off. A transactional caller saves them before and restores
  // them after a failed call, so a retried run matches one that never failed bit for bit.
  virtual void save_caches() {}
  virtual void restore_caches() {}
  virtual void reset_caches() {}  // back to the state of a fresh model (Simulation::reset)

  // --- Conveniences over evaluate(). ---
  double energy(const Nodes& x);
  // f += internal forces at x.
  void add_forces(const Nodes& x, Nodes& f);
  // A += scale * K(x) of the given kind.
  void add_stiffness(const Nodes& x, StiffnessKind kind, double scale, BlockSparseMatrix& A);
  // Point mass per node (n): the lumped mass matrix's diagonal.
  Vec lumped_masses() const;

 protected:
  // Throws InvalidInput when x, the force buffer or the matrix do not fit this model.
  void check_evaluation(const Nodes& x, const Request& what, const Results& out) const;
};

}  // namespace corotate
