#include "corotate/modal/partial_rotation.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <string>

namespace corotate {

namespace {

// The rotation by the rotation vector v (Rodrigues); identity for |v| = 0.
Mat3 rotation_about(const Vec3& v) {
  const double angle = v.norm();
  if (angle == 0.0) return Mat3::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

}  // namespace

Mat3 least_squares_rotation(const Mat3& covariance) {
  const Eigen::JacobiSVD<Mat3> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Mat3 V = svd.matrixV(), U = svd.matrixU();
  Mat3 reflection = Mat3::Identity();
  if ((V * U.transpose()).determinant() < 0) reflection(2, 2) = -1.0;  // a proper rotation only
  return V * reflection * U.transpose();
}

PartialRotation::PartialRotation(const double* rest, Index n_nodes,
                                 const std::vector<std::vector<long long>>& representative,
                                 const std::vector<long long>& blended_nodes, const double* weights)
    : n_nodes_(n_nodes) {
  if (n_nodes < 1) throw InvalidInput("partial rotation needs at least one node");
  const Index k = Index(representative.size());
  if (k < 1) throw InvalidInput("partial rotation needs at least one domain");
  const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>> X(rest, 3, n_nodes);
  if (!X.allFinite()) throw InvalidInput("rest positions must be finite");
  const double extent = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
  for (Index d = 0; d < k; ++d) {
    const auto& points = representative[d];
    const std::string what = "representative points of domain " + std::to_string(d);
    if (points.size() < 3) throw InvalidInput(what + ": need at least three");
    DomainPoints dp{Index(representative_nodes_.size()), Index(points.size()), Nodes(3, Index(points.size()))};
    for (Index i = 0; i < dp.count; ++i) {
      const long long node = points[i];
      if (node < 0 || node >= n_nodes)
        throw InvalidInput(what + ": node index " + std::to_string(node) + " is out of range [0, " +
                           std::to_string(n_nodes) + ")");
      dp.centred_rest.col(i) = X.col(node);
      representative_nodes_.push_back(node);
    }
    dp.centred_rest.colwise() -= dp.centred_rest.rowwise().mean();
    // A rotation is fixed by the points only if they span a plane: two singular values of
    // the centred points must be clearly nonzero.
    const Vec3 spread = Eigen::JacobiSVD<Mat3>(dp.centred_rest * dp.centred_rest.transpose()).singularValues();
    if (!(std::sqrt(spread[1]) > 1e-9 * extent))
      throw InvalidInput(what + " are coincident or on one line: they do not fix a rotation");
    domain_points_.push_back(std::move(dp));
  }
  const Index m = Index(blended_nodes.size());
  blend_weights_.resize(0, k);
  node_slot_.assign(n_nodes, kUntouched);
  Index blended = 0;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> W(weights, m, k);
  for (Index j = 0; j < m; ++j) {
    const long long node = blended_nodes[j];
    if (node < 0 || node >= n_nodes)
      throw InvalidInput("blended node index " + std::to_string(node) + " is out of range [0, " +
                         std::to_string(n_nodes) + ")");
    if (node_slot_[node] != kUntouched) throw InvalidInput("blended node " + std::to_string(node) + " is listed twice");
    const auto w = W.row(j);
    if (!w.allFinite() || (w.array() < 0).any() || w.sum() > 1.0 + 1e-12)
      throw InvalidInput("blend weights of node " + std::to_string(node) +
                         " must be finite, >= 0 and sum to at most 1");
    Index d;
    if (w.maxCoeff(&d) == 1.0 && w.sum() == 1.0) {
      node_slot_[node] = int(d);  // one domain's rotation, shared
    } else {
      node_slot_[node] = int(k + blended++);
    }
  }
  blend_weights_.resize(blended, k);
  for (Index j = 0; j < m; ++j)
    if (node_slot_[blended_nodes[j]] >= k) blend_weights_.row(node_slot_[blended_nodes[j]] - k) = W.row(j);
  rotations_.assign(k, Mat3::Identity());
  half_rotations_.assign(k, Mat3::Identity());
  rotation_vectors_.assign(k, Vec3::Zero());
  representative_displacements_.assign(3 * representative_nodes_.size(), 0.0);
}

void PartialRotation::fit(const double* representative_displacements) {
  for (Index d = 0; d < n_domains(); ++d) {
    const DomainPoints& dp = domain_points_[d];
    // Moved points centred: centred rest + displacement - mean displacement.
    const Eigen::Map<const Nodes> u(representative_displacements + 3 * dp.first, 3, dp.count);
    const Vec3 mean = u.rowwise().mean();
    Mat3 covariance = Mat3::Zero();  // sum_i a_i b_i^T
    for (Index i = 0; i < dp.count; ++i)
      covariance.noalias() += dp.centred_rest.col(i) * (dp.centred_rest.col(i) + u.col(i) - mean).transpose();
    rotations_[d] = least_squares_rotation(covariance);
    const Eigen::AngleAxisd angle_axis(rotations_[d]);
    rotation_vectors_[d] = angle_axis.angle() * angle_axis.axis();
    half_rotations_[d] = rotation_about(0.5 * rotation_vectors_[d]);
  }
}

void PartialRotation::rotate(const long long* nodes, Index count, double* u) const {
  const Index k = n_domains();
  for (Index i = 0; i < count; ++i) {
    const int slot = node_slot_[nodes ? nodes[i] : i];
    if (slot == kUntouched) continue;
    Eigen::Map<Vec3> ui(u + 3 * i);
    if (slot < k) {
      ui = half_rotations_[slot] * ui;
      continue;
    }
    Vec3 v = Vec3::Zero();
    for (Index d = 0; d < k; ++d) v += blend_weights_(slot - k, d) * rotation_vectors_[d];
    ui = rotation_about(0.5 * v) * ui;
  }
}

}  // namespace corotate
