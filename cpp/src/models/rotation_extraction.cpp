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
  constexpr double converged_step = 1e-6;  // quadratic: the remaining error is ~1e-12
  if (!F.allFinite()) return q.toRotationMatrix();
  const double scale = F.norm();
  if (!(scale > 0)) return q.toRotationMatrix();
  const Mat3 A = F / scale;
  for (int it = 0; it < max_iterations; ++it) {
    const Mat3 R = q.toRotationMatrix();
    const Vec3 g = R.col(0).cross(A.col(0)) + R.col(1).cross(A.col(1)) + R.col(2).cross(A.col(2));
    const Mat3 B = A * R.transpose();
    const double trace = B.trace();
    // H = tr(B) I - sym(B), solved by its adjugate when its leading minors say it is
    // positive definite (a 3x3 LLT costs more and tells the same).
    const double h00 = trace - B(0, 0), h11 = trace - B(1, 1), h22 = trace - B(2, 2);
    const double h01 = -0.5 * (B(0, 1) + B(1, 0)), h02 = -0.5 * (B(0, 2) + B(2, 0)), h12 = -0.5 * (B(1, 2) + B(2, 1));
    const double c00 = h11 * h22 - h12 * h12, c01 = h02 * h12 - h01 * h22, c02 = h01 * h12 - h02 * h11;
    const double det = h00 * c00 + h01 * c01 + h02 * c02;
    Vec3 w;
    if (h00 > 0 && h00 * h11 - h01 * h01 > 0 && det > 0) {
      const double c11 = h00 * h22 - h02 * h02, c12 = h01 * h02 - h00 * h12, c22 = h00 * h11 - h01 * h01;
      w = Vec3(c00 * g.x() + c01 * g.y() + c02 * g.z(), c01 * g.x() + c11 * g.y() + c12 * g.z(),
               c02 * g.x() + c12 * g.y() + c22 * g.z()) /
          det;
    } else {
      w = g / (std::abs(trace) + 1e-9);
    }
    double angle = w.norm();
    if (!(angle < 1.0)) {  // trust region: at most one radian per iteration
      if (!std::isfinite(angle)) break;
      w /= angle;
      angle = 1.0;
    }
    // q <- exp(w/2) q; for small angles the series avoids sin and cos (error < 1e-17).
    double c, s_over_angle;
    if (angle < 1e-3) {
      const double a2 = angle * angle;
      c = 1 - a2 / 8;
      s_over_angle = 0.5 - a2 / 48;
    } else {
      c = std::cos(0.5 * angle);
      s_over_angle = std::sin(0.5 * angle) / angle;
    }
    const Eigen::Quaterniond dq(c, s_over_angle * w.x(), s_over_angle * w.y(), s_over_angle * w.z());
    q = dq * q;
    q.normalize();
    if (angle < converged_step) return q.toRotationMatrix();
  }
  const Mat3 R = polar_rotation_svd(F);
  q = Eigen::Quaterniond(R);
  return R;
}

}  // namespace corotate
