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

// The same for count elements at once (F, q, R: arrays of count): the iterations of several
// elements run side by side, vectorised, which is several times faster per element than one
// call each (one element's iteration is a serial chain of dependent operations).
void extract_rotations(const Mat3* F, Eigen::Quaterniond* q, Mat3* R, int count);
// The same to about 1e-6 rad instead of round-off, for rotations that only need to be close
// (a preconditioner's frames): from a warm start that moved less than ~1e-3 rad since the
// last call, one iteration instead of two.
void extract_rotations_roughly(const Mat3* F, Eigen::Quaterniond* q, Mat3* R, int count);
// The same in structure-of-arrays form, F[i][j][k] and R[i][j][k] for problem k < count <=
// kRotationLanes: for a batched element sweep that keeps its elements in lanes throughout.
inline constexpr int kRotationLanes = 16;
void extract_rotations(const double (&F)[3][3][kRotationLanes], Eigen::Quaterniond* q,
                       double (&R)[3][3][kRotationLanes], int count);

// What the derivative of the polar rotation needs, shared by the co-rotated tangents: for
// F = R S with S symmetric, a change dF rotates R by dR = R [theta]x with
//     (tr(S) I - S) theta = vee(R^T dF - dF^T R).
// Gives S = sym(R^T F) and H^-1 = (tr(S) I - S)^-1; false (nothing set) where H is near
// singular, i.e. the element is inverted or flat and its rotation has no derivative.
inline bool polar_rotation_derivative(const Mat3& R, const Mat3& F, Mat3& S, Mat3& H_inv) {
  const Mat3 RtF = R.transpose() * F;
  const Mat3 sym = 0.5 * (RtF + RtF.transpose());
  Mat3 H = -sym;
  H.diagonal().array() += sym.trace();
  const double det = H.determinant(), scale = H.cwiseAbs().maxCoeff();
  if (!(det > 1e-8 * scale * scale * scale)) return false;
  S = sym;
  H_inv = H.inverse();
  return true;
}

}  // namespace corotate
