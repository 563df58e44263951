#include "corotate/modal/modal_basis.hpp"

#include <string>

namespace corotate {

void check_node_indices(const long long* nodes, Index count, Index n_nodes) {
  for (Index k = 0; k < count; ++k)
    if (nodes[k] < 0 || nodes[k] >= n_nodes)
      throw InvalidInput("node index " + std::to_string(nodes[k]) + " is out of range [0, " + std::to_string(n_nodes) +
                         ")");
}

void recover_displacements(const BasisMap& basis, const VecRef& q, const long long* nodes, Index count, double* out) {
  // One short dot product per DOF row (r entries, contiguous in the row-major basis): the basis
  // is read once, front to back, and the same code serves subsets. For 300,000 rows of 20 it
  // takes the time of reading the basis (interleaved C++ loops on a quiet machine: 1.9-2.2 ms,
  // a plain sum of the basis 1.8-2.2 ms, Eigen's row-major product 2.1-2.4 ms; a 3-row SSE2
  // kernel and software prefetching did no better, warm or with the basis evicted).
  const Index r = basis.cols();
  const double* data = basis.data();
  auto row_dot = [&](Index row) { return Eigen::Map<const Vec>(data + row * r, r).dot(q); };
  if (nodes == nullptr) {
    for (Index i = 0; i < basis.rows(); ++i) out[i] = row_dot(i);
    return;
  }
  for (Index k = 0; k < count; ++k)
    for (Index a = 0; a < 3; ++a) out[3 * k + a] = row_dot(3 * nodes[k] + a);
}

void recover_displacements(const float* basis, Index rows, Index r, const VecRef& q, const long long* nodes,
                           Index count, double* out) {
  // Single-precision dot products (four lanes per SSE register): the basis is only good to
  // float precision anyway. q in float lives on the stack for r <= 64 (no allocation).
  using SmallVecF = Eigen::Matrix<float, Eigen::Dynamic, 1, 0, 64, 1>;
  if (r > 64) throw InvalidInput("single-precision recovery supports up to 64 basis vectors");
  const SmallVecF qf = q.cast<float>();
  auto row_dot = [&](Index row) { return double(Eigen::Map<const Eigen::VectorXf>(basis + row * r, r).dot(qf)); };
  if (nodes == nullptr) {
    for (Index i = 0; i < rows; ++i) out[i] = row_dot(i);
    return;
  }
  for (Index k = 0; k < count; ++k)
    for (Index a = 0; a < 3; ++a) out[3 * k + a] = row_dot(3 * nodes[k] + a);
}

void project_nodal_forces(const BasisMap& basis, const long long* nodes, Index count, const double* forces,
                          double* out) {
  const Index r = basis.cols();
  Eigen::Map<Vec> p(out, r);
  p.setZero();
  for (Index k = 0; k < count; ++k)
    p.noalias() += basis.block(3 * nodes[k], 0, 3, r).transpose() * Eigen::Map<const Vec3>(forces + 3 * k);
}

}  // namespace corotate
