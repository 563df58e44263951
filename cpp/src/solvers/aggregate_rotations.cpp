#include "corotate/solvers/aggregate_rotations.hpp"

#include "corotate/models/rotation_extraction.hpp"

namespace corotate {

std::vector<int> aggregate_nodes(const BlockSparseMatrix& pattern, int* count) {
  const Index n = pattern.num_nodes();
  const auto& start = pattern.row_start();
  const auto& cols = pattern.columns();
  std::vector<int> agg(n, -1);
  int m = 0;
  for (Index i = 0; i < n; ++i) {
    if (agg[i] >= 0) continue;
    bool free = true;
    for (int k = start[i]; k < start[i + 1] && free; ++k) free = agg[cols[k]] < 0;
    if (!free) continue;
    for (int k = start[i]; k < start[i + 1]; ++k) agg[cols[k]] = m;
    ++m;
  }
  for (Index i = 0; i < n; ++i) {
    if (agg[i] >= 0) continue;
    for (int k = start[i]; k < start[i + 1]; ++k)
      if (agg[cols[k]] >= 0 && cols[k] != i) {
        agg[i] = agg[cols[k]];
        break;
      }
    if (agg[i] < 0) agg[i] = m++;  // isolated node
  }
  *count = m;
  return agg;
}

void AggregateRotations::build(const BlockSparseMatrix& pattern, const Nodes& built_at) {
  int m = 0;
  const std::vector<int> aggregate = aggregate_nodes(pattern, &m);
  build(aggregate, m, built_at);
}

void AggregateRotations::build(const std::vector<int>& aggregate_of_node, int m, const Nodes& built_at) {
  const Index n = static_cast<Index>(aggregate_of_node.size());
  if (built_at.cols() != n)
    throw InvalidInput("aggregate rotations: positions of " + std::to_string(built_at.cols()) + " nodes for a " +
                       std::to_string(n) + "-node system");
  aggregate_ = aggregate_of_node;  // (its storage reused when built again)
  centre_.assign(m, Vec3::Zero());
  size_.assign(m, 0);
  for (Index i = 0; i < n; ++i) {
    centre_[aggregate_[i]] += built_at.col(i);
    ++size_[aggregate_[i]];
  }
  offsets_.resize(3, n);
  for (Index i = 0; i < n; ++i)
    offsets_.col(i) = built_at.col(i) - centre_[aggregate_[i]] / double(size_[aggregate_[i]]);
  rotations_.assign(m, Mat3::Identity());
  covariance_.assign(m, Mat3::Zero());
  rotation_guess_.assign(m, Eigen::Quaterniond::Identity());
  rotated_ = false;
}

void AggregateRotations::update(const Nodes& x) {
  const Index m = num_aggregates();
  if (x.cols() != offsets_.cols())
    throw InvalidInput("aggregate rotations: positions of " + std::to_string(x.cols()) + " nodes for a " +
                       std::to_string(offsets_.cols()) + "-node system");
  for (Index a = 0; a < m; ++a) covariance_[a].setZero();
  // sum_i (x_i - c_x)(X_i - c_X)^T = sum_i x_i (X_i - c_X)^T: the offsets sum to zero.
  for (Index i = 0; i < x.cols(); ++i) covariance_[aggregate_[i]].noalias() += x.col(i) * offsets_.col(i).transpose();
  // All aggregates at once: their iterations run side by side (rotation_extraction.hpp).
  extract_rotations(covariance_.data(), rotation_guess_.data(), rotations_.data(), static_cast<int>(m));
  rotated_ = false;
  for (Index a = 0; a < m; ++a) rotated_ = rotated_ || !rotations_[a].isIdentity(1e-12);
}

std::vector<int> connected_parts(const BlockSparseMatrix& pattern, int* count) {
  const Index n = pattern.num_nodes();
  std::vector<int> part(n, -1), stack;
  int m = 0;
  for (Index seed = 0; seed < n; ++seed) {
    if (part[seed] >= 0) continue;
    part[seed] = m;
    stack.assign(1, static_cast<int>(seed));
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      for (int k = pattern.row_start()[i]; k < pattern.row_start()[i + 1]; ++k) {
        const int j = pattern.columns()[k];
        if (part[j] < 0) part[j] = m, stack.push_back(j);
      }
    }
    ++m;
  }
  *count = m;
  return part;
}

}  // namespace corotate
