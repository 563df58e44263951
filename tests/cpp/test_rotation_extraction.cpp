// Rotation extraction: the polar rotation of F = R S (S symmetric positive definite) is R,
// both by the SVD and by the warm-started iteration; an inverted F still gives a rotation.
#include <algorithm>
#include <limits>

#include "corotate/models/rotation_extraction.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

// Symmetric positive definite with eigenvalues in [0.5, 2]: condition number <= 4, so the
// rotation is determined to round-off (its error is ~ eps |F| / (s_i + s_j) ~ 1e-16).
Mat3 random_stretch() {
  const Mat3 Q = fixtures::random_rotation();
  const Vec3 s(fixtures::uniform(0.5, 2), fixtures::uniform(0.5, 2), fixtures::uniform(0.5, 2));
  return Q * s.asDiagonal() * Q.transpose();
}

bool is_rotation(const Mat3& R) {
  return (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-14 && std::abs(R.determinant() - 1) < 1e-14;
}

}  // namespace

TEST(polar_rotation_svd_of_rotated_stretch_is_the_rotation) {
  for (int k = 0; k < 20; ++k) {
    const Mat3 R = fixtures::random_rotation(), F = R * random_stretch();
    const Mat3 found = polar_rotation_svd(F);
    CHECK(is_rotation(found));
    CHECK_NEAR((found - R).cwiseAbs().maxCoeff(), 0.0, 1e-13);
  }
}

TEST(extract_rotation_converges_to_the_polar_rotation) {
  for (int k = 0; k < 20; ++k) {
    const Mat3 R = fixtures::random_rotation(), F = R * random_stretch();
    // From the identity (a cold start, possibly far away) and from a nearby warm start.
    Eigen::Quaterniond cold = Eigen::Quaterniond::Identity();
    Eigen::Quaterniond warm(Eigen::AngleAxisd(0.1, Vec3::UnitX()) * Eigen::Quaterniond(R));
    for (Eigen::Quaterniond* q : {&cold, &warm}) {
      const Mat3 found = extract_rotation(F, *q);
      CHECK(is_rotation(found));
      // Converged Newton iterations stop with a step below 1e-6, leaving an error ~1e-12.
      CHECK_NEAR((found - R).cwiseAbs().maxCoeff(), 0.0, 1e-10);
      CHECK_NEAR((q->toRotationMatrix() - R).cwiseAbs().maxCoeff(), 0.0, 1e-10);  // q updated
    }
  }
}

TEST(polar_rotation_of_an_inverted_matrix_is_proper) {
  for (int k = 0; k < 10; ++k) {
    const Mat3 R = fixtures::random_rotation();
    const Mat3 F = R * Vec3(1.5, 1.0, -0.4).asDiagonal();  // det F < 0
    const Mat3 found = polar_rotation_svd(F);
    CHECK(is_rotation(found));
    // The closest rotation keeps the two large axes and flips the smallest: R itself.
    CHECK_NEAR((found - R).cwiseAbs().maxCoeff(), 0.0, 1e-13);
  }
}

// The batched form: 21 elements (two full batches of eight and a partial one) with warm
// starts near and far, a zero F and a non-finite F among them; every rotation and quaternion
// must match the one-at-a-time result to the iterations' accuracy, and the zero and
// non-finite lanes keep their quaternion, as extract_rotation does.
TEST(batched_rotations_match_one_at_a_time) {
  constexpr int n = 21;
  Mat3 F[n], R_batch[n], R_true[n];
  Eigen::Quaterniond q_batch[n], q_single[n];
  for (int k = 0; k < n; ++k) {
    R_true[k] = fixtures::random_rotation();
    F[k] = R_true[k] * random_stretch();
    const double off = (k % 3 == 0) ? 1.5 : 0.01;  // some far (lockstep not enough), most near
    q_batch[k] = q_single[k] =
        Eigen::Quaterniond(Eigen::AngleAxisd(off, Vec3(1, 2, 3).normalized()) * Eigen::Quaterniond(R_true[k]));
  }
  F[5].setZero();
  F[13](1, 2) = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Quaterniond q5 = q_batch[5], q13 = q_batch[13];
  extract_rotations(F, q_batch, R_batch, n);
  for (int k = 0; k < n; ++k) {
    const Mat3 R_single = extract_rotation(F[k], q_single[k]);
    CHECK(is_rotation(R_batch[k]));
    CHECK_NEAR((R_batch[k] - R_single).cwiseAbs().maxCoeff(), 0.0, 1e-10);
    CHECK_NEAR((R_batch[k] - q_batch[k].toRotationMatrix()).cwiseAbs().maxCoeff(), 0.0, 1e-14);
    if (k != 5 && k != 13) CHECK_NEAR((R_batch[k] - R_true[k]).cwiseAbs().maxCoeff(), 0.0, 1e-10);
  }
  CHECK(q_batch[5].coeffs() == q5.coeffs());
  CHECK(q_batch[13].coeffs() == q13.coeffs());
}

// The rough form: the polar rotation to ~1e-6 (a last step below 1e-3 rad leaves about its
// square), from warm starts near and far; a zero F keeps its quaternion.
TEST(rough_rotations_are_within_a_millionth) {
  constexpr int n = 21;
  Mat3 F[n], R_rough[n], R_true[n];
  Eigen::Quaterniond q[n];
  for (int k = 0; k < n; ++k) {
    R_true[k] = fixtures::random_rotation();
    F[k] = R_true[k] * random_stretch();
    const double off = (k % 3 == 0) ? 1.5 : (k % 3 == 1) ? 0.01 : 1e-4;
    q[k] = Eigen::Quaterniond(Eigen::AngleAxisd(off, Vec3(1, 2, 3).normalized()) * Eigen::Quaterniond(R_true[k]));
  }
  F[7].setZero();
  const Eigen::Quaterniond q7 = q[7];
  extract_rotations_roughly(F, q, R_rough, n);
  double worst = 0;
  for (int k = 0; k < n; ++k) {
    CHECK(is_rotation(R_rough[k]));
    if (k != 7) worst = std::max(worst, (R_rough[k] - R_true[k]).cwiseAbs().maxCoeff());
  }
  CHECK(worst < 1e-6);
  CHECK(q[7].coeffs() == q7.coeffs());
}

// Full batches whose lanes all start near (0.01 rad off: every step below the small-step
// bound): the iteration without square roots or trust region, the quaternion normalised by a
// series, the rotations stored lane for lane. The same rotations as one at a time, and
// quaternions that stay unit through a thousand calls that each turn every element a little
// (a body turning slowly, step after step: no drift of |q| from the series).
TEST(full_batches_of_near_warm_starts_stay_exact_and_unit) {
  constexpr int n = 32;
  Mat3 F[n], R_batch[n], R_true[n], S[n];
  Eigen::Quaterniond q[n], q_single[n];
  for (int k = 0; k < n; ++k) {
    R_true[k] = fixtures::random_rotation();
    S[k] = random_stretch();
    q[k] = q_single[k] =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.01, Vec3(1, 2, 3).normalized()) * Eigen::Quaterniond(R_true[k]));
  }
  const Mat3 turn = Eigen::AngleAxisd(2e-3, Vec3(3, -1, 2).normalized()).toRotationMatrix();
  double worst = 0, worst_norm = 0;
  for (int call = 0; call < 1000; ++call) {
    for (int k = 0; k < n; ++k) {
      if (call > 0) R_true[k] = turn * R_true[k];
      F[k] = R_true[k] * S[k];
    }
    extract_rotations(F, q, R_batch, n);
    for (int k = 0; k < n; ++k) {
      worst = std::max(worst, (R_batch[k] - R_true[k]).cwiseAbs().maxCoeff());
      worst_norm = std::max(worst_norm, std::abs(q[k].norm() - 1));
    }
    if (call == 0)
      for (int k = 0; k < n; ++k) {
        CHECK(is_rotation(R_batch[k]));
        CHECK_NEAR((R_batch[k] - extract_rotation(F[k], q_single[k])).cwiseAbs().maxCoeff(), 0.0, 1e-12);
      }
  }
  CHECK(worst < 1e-10);
  CHECK(worst_norm < 1e-14);
}
