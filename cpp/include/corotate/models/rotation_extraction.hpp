// Rotation part of a deformation gradient F, robust to inverted elements.
#pragma once

#include <Eigen/Geometry>

#include "corotate/common.hpp"

namespace corotate {

// Polar rotation by SVD with the sign fix: R = U diag(1, 1, det(U V^T)) V^T, which is the
// rotation (det R = +1) closest to F, also when det F <= 0.
Mat3 polar_rotation_svd(const Mat3& F);

// The same rotation by the iterative method of Mueller et al. 2016 ("A robust method to
// extract the rotational part of deformations"), warm-started from the quaternion q of the
// previous step, which it updates, with full Newton steps on SO(3): two or three cheap
// iterations per element instead of an SVD, accurate to round-off;
// falls back to the SVD when the iteration does not converge.
Mat3 extract_rotation(const Mat3& F, Eigen::Quaterniond& q);

}  // namespace corotate
