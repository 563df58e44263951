// Partial rotation of modal displacements (the paper's §3.2), the per-frame part.
//
// A linear (modal) displacement field moves every point along a straight line; domains of a
// structure that turn as a whole (a beam's span, the arms of an axle) are given their turn
// back. Per frame and domain k:
//   1. fit(): the least-squares rotation R_k of the domain's representative points from rest to
//      modally displaced positions (Kabsch: the polar factor of the points' covariance), and
//      its rotation vector theta_k;
//   2. rotate(): each node's displacement u becomes R(v / 2) u with v = sum_k w_k theta_k, the
//      node's blend of the domains' rotation vectors (weights set up once, e.g. by the Python
//      PartialRotation: 1 on a domain, fading out over a band around it).
// Half the angle because, for a rigid turn by theta at distance r, the linear displacement is
// the tangent (length r theta) and the true one the chord (length 2 r sin(theta/2), turned by
// theta/2 from the tangent): turning by theta/2 is right to second order in theta.
//
// Nodes whose only weight is 1 on one domain share that domain's half rotation matrix (one
// 3x3 product per node); blended nodes get their own (a sine and a cosine). fit() and rotate()
// allocate nothing.
#pragma once

#include <vector>

#include "corotate/common.hpp"

namespace corotate {

// The proper rotation R minimising sum_i |R a_i - b_i|^2 over centred point pairs (a_i, b_i),
// from their covariance H = sum_i a_i b_i^T: the polar factor of H^T (Kabsch), a reflection
// turned into the nearest rotation.
Mat3 least_squares_rotation(const Mat3& covariance);

class PartialRotation {
 public:
  // rest: n x 3 row-major rest positions. representative[k]: the nodes of domain k whose fit
  // gives its rotation (at least three, not on one line). blended_nodes (m, distinct) and
  // weights (m x k row-major, finite, >= 0, each row summing to at most 1): the nodes that
  // turn and their weights per domain; the other nodes keep their displacement.
  PartialRotation(const double* rest, Index n_nodes, const std::vector<std::vector<long long>>& representative,
                  const std::vector<long long>& blended_nodes, const double* weights);

  Index n_nodes() const { return n_nodes_; }
  Index n_domains() const { return Index(domain_points_.size()); }
  // All domains' representative nodes, domain after domain: the rows fit() reads.
  const std::vector<long long>& representative_nodes() const { return representative_nodes_; }
  // A buffer of 3 x representative_nodes().size() doubles the caller may recover the
  // representative points' displacements into (so a frame allocates nothing).
  double* representative_buffer() { return representative_displacements_.data(); }

  // Fit each domain's rotation to the displacements of representative_nodes() (count x 3
  // row-major, finite: the caller checks) and set the per-domain half rotations.
  void fit(const double* representative_displacements);
  // u (count x 3 row-major) of the given nodes (nullptr: all n nodes) rotated in place by their
  // blended half rotation of the last fit().
  void rotate(const long long* nodes, Index count, double* u) const;

  const Mat3& rotation(Index domain) const { return rotations_[domain]; }          // R_k of the last fit
  const Vec3& rotation_vector(Index domain) const { return rotation_vectors_[domain]; }  // theta_k

 private:
  struct DomainPoints {
    Index first, count;  // into representative_nodes_
    Nodes centred_rest;  // 3 x count, rest positions minus their mean
  };
  static constexpr int kUntouched = -1;

  Index n_nodes_;
  std::vector<long long> representative_nodes_;
  std::vector<DomainPoints> domain_points_;
  // Per node: kUntouched, a domain index d (weight 1 on d alone), or n_domains + j for row j of
  // blend_weights_.
  std::vector<int> node_slot_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> blend_weights_;
  std::vector<Mat3> rotations_, half_rotations_;
  std::vector<Vec3> rotation_vectors_;
  std::vector<double> representative_displacements_;
};

}  // namespace corotate
