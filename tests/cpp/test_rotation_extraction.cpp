// Rotation extraction: the polar rotation of F = R S (S symmetric positive definite) is R,
// both by the SVD and by the warm-started iteration; an inverted F still gives a rotation.
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
