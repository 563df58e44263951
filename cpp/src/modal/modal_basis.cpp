#include "corotate/modal/modal_basis.hpp"

#include <string>

namespace corotate {

void check_node_indices(const long long* nodes, Index count, Index n_nodes) {
  for (Index k = 0; k < count; ++k)
    if (nodes[k] < 0 || nodes[k] >= n_nodes)
      throw InvalidInput("node index " + std::to_string(nodes[k]) + " is out of range [0, " + std::to_string(n_nodes) +
                         ")");
}

void recover_displacements(const BasisMap& basis, const Vec& q, const long long* nodes, Index count, double* out) {
  if (nodes == nullptr) {
    Eigen::Map<Vec>(out, basis.rows()).noalias() = basis * q;
    return;
  }
  const Index r = basis.cols();
  for (Index k = 0; k < count; ++k) {
    const Index row = 3 * nodes[k];
    Eigen::Map<Vec3>(out + 3 * k).noalias() = basis.block(row, 0, 3, r) * q;
  }
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
