#include "corotate/solvers/node_rotations.hpp"

#include "corotate/cpu_clones.hpp"
#include "corotate/models/rotation_extraction.hpp"
#include "corotate/sparse/symmetric_product.hpp"  // Four

namespace corotate {

void NodeRotations::build(const BlockSparseMatrix& pattern, const Nodes& built_at) {
  const Index n = pattern.num_nodes();
  if (built_at.cols() != n)
    throw InvalidInput("node rotations: positions of " + std::to_string(built_at.cols()) + " nodes for a " +
                       std::to_string(n) + "-node system");
  start_ = pattern.row_start();
  stencil_ = pattern.columns();
  offsets_.resize(3 * stencil_.size());
  for (Index i = 0; i < n; ++i) {
    Vec3 centre = Vec3::Zero();
    for (int k = start_[i]; k < start_[i + 1]; ++k) centre += built_at.col(stencil_[k]);
    centre /= double(start_[i + 1] - start_[i]);
    for (int k = start_[i]; k < start_[i + 1]; ++k)
      Eigen::Map<Vec3>(offsets_.data() + 3 * k) = built_at.col(stencil_[k]) - centre;
  }
  covariance_.assign(n, Mat3::Zero());
  rotations_.assign(n, Mat3::Identity());
  guess_.assign(n, Eigen::Quaterniond::Identity());
  rotated_ = false;
}

namespace {

// covariance[i] = sum over i's stencil of x_j (X_j - c_i)^T, column by column: four-wide sums
// of x_j times one offset entry, compiled per instruction set.
COROTATE_CPU_CLONES void stencil_covariances(const int* start, const int* stencil, const double* offsets,
                                             const double* x, Index n, Mat3* covariance) {
  using V = Four<double>::type;
  for (Index i = 0; i < n; ++i) {
    V c0 = {0, 0, 0, 0}, c1 = c0, c2 = c0;
    for (int k = start[i]; k < start[i + 1]; ++k) {
      const double* xj = x + 3 * stencil[k];
      const V v = {xj[0], xj[1], xj[2], 0.0};
      const double* o = offsets + 3 * k;
      c0 += v * o[0];
      c1 += v * o[1];
      c2 += v * o[2];
    }
    double* C = covariance[i].data();  // column-major
    for (int r = 0; r < 3; ++r) C[r] = c0[r], C[3 + r] = c1[r], C[6 + r] = c2[r];
  }
}

}  // namespace

void NodeRotations::update(const Nodes& x) {
  const Index n = static_cast<Index>(rotations_.size());
  if (x.cols() != n)
    throw InvalidInput("node rotations: positions of " + std::to_string(x.cols()) + " nodes for a " +
                       std::to_string(n) + "-node system");
  stencil_covariances(start_.data(), stencil_.data(), offsets_.data(), x.data(), n, covariance_.data());
  // All nodes at once: their iterations run side by side (rotation_extraction.hpp); a
  // preconditioner's frames need not be exact to round-off.
  extract_rotations_roughly(covariance_.data(), guess_.data(), rotations_.data(), static_cast<int>(n));
  rotated_ = false;
  for (Index i = 0; i < n && !rotated_; ++i) rotated_ = !rotations_[i].isIdentity(1e-12);
}

}  // namespace corotate
