// First and second derivatives of J = det F for 3 x 3 F, in column-major vec order.
// With columns f0, f1, f2 of F, J = f0 . (f1 x f2), so
//     dJ/dF = cof F = [f1 x f2, f2 x f0, f0 x f1],
// and the Hessian is made of cross-product matrices of the columns (it is linear in F):
//     d2J/dF2 = [[0, -[f2], [f1]], [[f2], 0, -[f0]], [-[f1], [f0], 0]].
// Used by every law with a volume term (Neo-Hookean, fixed co-rotated).
#pragma once

#include "corotate/common.hpp"

namespace corotate {

inline Mat3 cofactor(const Mat3& F) {
  Mat3 g;
  g.col(0) = F.col(1).cross(F.col(2));
  g.col(1) = F.col(2).cross(F.col(0));
  g.col(2) = F.col(0).cross(F.col(1));
  return g;
}

inline Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

inline Eigen::Matrix<double, 9, 9> determinant_hessian(const Mat3& F) {
  Eigen::Matrix<double, 9, 9> H = Eigen::Matrix<double, 9, 9>::Zero();
  const Mat3 c0 = cross_matrix(F.col(0)), c1 = cross_matrix(F.col(1)), c2 = cross_matrix(F.col(2));
  H.block<3, 3>(0, 3) = -c2;
  H.block<3, 3>(0, 6) = c1;
  H.block<3, 3>(3, 0) = c2;
  H.block<3, 3>(3, 6) = -c0;
  H.block<3, 3>(6, 0) = -c1;
  H.block<3, 3>(6, 3) = c0;
  return H;
}

}  // namespace corotate
