#include "corotate/models/rotation_extraction.hpp"

#include <Eigen/SVD>
#include <cmath>

namespace corotate {

Mat3 polar_rotation_svd(const Mat3& F) {
  Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU();
  const Mat3& V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(2) *= -1;  // smallest singular value flips
  return U * V.transpose();
}

Mat3 extract_rotation(const Mat3& F, Eigen::Quaterniond& q) {
  // The polar rotation maximises tr(R^T F) over rotations. With R = exp([w]) R_c and
  // B = F R_c^T, that objective is, to second order in w,
  //     tr(B) + g.w - 1/2 w^T (tr(B) I - sym(B)) w,   g = sum_i r_i x f_i,
  // where r_i, f_i are the columns of R_c and F. Mueller et al. 2016 step along g scaled by
  // 1/tr(B), which converges linearly (rate 1/3 near a rotation). Taking the full Newton step
  // w = (tr(B) I - sym(B))^-1 g converges quadratically: from the previous step's rotation,
  // two or three iterations reach round-off. Where that Hessian is not positive definite
  // (far from the answer) the Mueller step is the safe choice.
  constexpr int max_iterations = 20;
  constexpr double converged_step = 1e-8;  // the next step would be ~1e-16: round-off
  if (!F.allFinite()) return q.toRotationMatrix();
  const double scale = F.norm();
  if (!(scale > 0)) return q.toRotationMatrix();
  const Mat3 A = F / scale;
  for (int it = 0; it < max_iterations; ++it) {
    const Mat3 R = q.toRotationMatrix();
    const Vec3 g = R.col(0).cross(A.col(0)) + R.col(1).cross(A.col(1)) + R.col(2).cross(A.col(2));
    const Mat3 B = A * R.transpose();
    Mat3 H = -0.5 * (B + B.transpose());
    H.diagonal().array() += B.trace();
    Eigen::LLT<Mat3> llt(H);
    Vec3 w = (llt.info() == Eigen::Success) ? Vec3(llt.solve(g)) : Vec3(g / (std::abs(B.trace()) + 1e-9));
    double angle = w.norm();
    if (!(angle < 1.0)) {  // trust region: at most one radian per iteration
      if (!std::isfinite(angle)) break;
      w /= angle;
      angle = 1.0;
    }
    if (angle > 0) {
      q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle)) * q;
      q.normalize();
    }
    if (angle < converged_step) return q.toRotationMatrix();
  }
  const Mat3 R = polar_rotation_svd(F);
  q = Eigen::Quaterniond(R);
  return R;
}

}  // namespace corotate
