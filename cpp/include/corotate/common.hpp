// Shared types and the two exception kinds of the core.
//
// Layout convention: node coordinates live in a 3 x n column-major matrix, so
// DOF index = 3*node + axis and the buffer is a NumPy (n, 3) C-order array.
#pragma once

#include <Eigen/Dense>
#include <stdexcept>
#include <string>

namespace corotate {

using Index = std::ptrdiff_t;
using Vec = Eigen::VectorXd;
using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;
using Nodes = Eigen::Matrix<double, 3, Eigen::Dynamic>;  // 3 x n, one column per node
using Connectivity = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;  // cells x nodes

// Bad input from the user (mesh, material, indices, parameters): becomes ValueError.
struct InvalidInput : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// A computation that could not finish (non-finite state, no convergence): RuntimeError.
struct SolverFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A system matrix that is not positive definite (an indefinite tangent, a singular block):
// the one solver failure a Newton iteration answers by falling back to a PSD stiffness.
struct NotPositiveDefinite : SolverFailure {
  using SolverFailure::SolverFailure;
};

// View a 3 x n node matrix as one flat DOF vector (no copy).
inline Eigen::Map<Vec> as_dofs(Nodes& x) { return {x.data(), x.size()}; }
inline Eigen::Map<const Vec> as_dofs(const Nodes& x) { return {x.data(), x.size()}; }

// Index of the first non-finite column, or -1 when all entries are finite.
Index first_non_finite_node(const Nodes& x);

// Throws InvalidInput naming the first node whose position, velocity or external force is
// not finite (what every simulation checks before it steps).
void check_finite_state(const Nodes& positions, const Nodes& velocities, const Nodes& external_forces);

}  // namespace corotate
