// Hyperelastic laws (StVK, stable Neo-Hookean, fixed co-rotated): the first Piola stress is
// the gradient of the energy density and the tangent is the gradient of the stress (central
// differences), the rest state is stress free with the linear-elastic tangent, and the energy
// does not change under rotation.
#include <limits>

#include "corotate/materials/fixed_corotated.hpp"
#include "corotate/materials/mooney_rivlin.hpp"
#include "corotate/materials/stable_neo_hookean.hpp"
#include "corotate/materials/stvk.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

// Nondimensional Lame parameters: W, P, dP/dF are all of order one for |F| of order one.
constexpr double lambda = 2.1, mu = 1.3;
// Central differences with step h: truncation h^2/6 |W'''| ~ 1e-10 plus round-off
// eps |W| / h ~ 1e-11; measured errors are up to 3e-10, so 1e-8 (relative to |P| when larger
// than one) leaves a 30x margin, while a term off by 1e-4 of its value already fails by 1000x.
constexpr double h = 1e-5, tolerance = 1e-8;

template <class Law, int D>
void check_stress_is_energy_gradient(const Law& law, const Eigen::Matrix<double, 3, D>& F) {
  using Matrix = Eigen::Matrix<double, 3, D>;
  const Matrix P = law.stress(F);
  Matrix fd;
  for (int j = 0; j < D; ++j)
    for (int i = 0; i < 3; ++i) {
      Matrix plus = F, minus = F;
      plus(i, j) += h;
      minus(i, j) -= h;
      fd(i, j) = (law.energy(plus) - law.energy(minus)) / (2 * h);
    }
  CHECK_NEAR((P - fd).cwiseAbs().maxCoeff(), 0.0, tolerance * std::max(1.0, P.cwiseAbs().maxCoeff()));
}

template <class Law, int D>
void check_tangent_is_stress_gradient(const Law& law, const Eigen::Matrix<double, 3, D>& F) {
  using Matrix = Eigen::Matrix<double, 3, D>;
  const Eigen::Matrix<double, 3 * D, 3 * D> A = law.tangent(F);
  Eigen::Matrix<double, 3 * D, 3 * D> fd;
  for (int c = 0; c < 3 * D; ++c) {
    Matrix plus = F, minus = F;
    plus(c % 3, c / 3) += h;  // column-major vec: c = i + 3 j
    minus(c % 3, c / 3) -= h;
    const Matrix dP = (law.stress(plus) - law.stress(minus)) / (2 * h);
    fd.col(c) = Eigen::Map<const Eigen::Matrix<double, 3 * D, 1>>(dP.data());
  }
  CHECK_NEAR((A - fd).cwiseAbs().maxCoeff(), 0.0, tolerance * std::max(1.0, A.cwiseAbs().maxCoeff()));
  CHECK_NEAR((A - A.transpose()).cwiseAbs().maxCoeff(), 0.0, 1e-13 * A.cwiseAbs().maxCoeff());
}

// At F = I: no stress, and dP = mu (dF + dF^T) + lambda tr(dF) I (linear elasticity).
template <class Law>
void check_rest_state(const Law& law) {
  const Mat3 I = Mat3::Identity();
  CHECK_NEAR(law.energy(I), 0.0, 1e-15);
  CHECK_NEAR(law.stress(I).cwiseAbs().maxCoeff(), 0.0, 1e-15);
  const Eigen::Matrix<double, 9, 9> A = law.tangent(I);
  for (int c = 0; c < 9; ++c) {
    Mat3 dF = Mat3::Zero();
    dF(c % 3, c / 3) = 1;
    Mat3 expected = mu * (dF + dF.transpose());
    expected.diagonal().array() += lambda * dF.trace();
    const Eigen::Matrix<double, 9, 1> column = A.col(c);
    CHECK_NEAR((column - Eigen::Map<const Eigen::Matrix<double, 9, 1>>(expected.data())).cwiseAbs().maxCoeff(), 0.0,
               1e-13);
  }
}

template <class Law>
void check_rotation_invariance(const Law& law, const Mat3& F) {
  const Mat3 R = fixtures::random_rotation();
  CHECK_NEAR(law.energy(Mat3(R * F)), law.energy(F), 1e-13 * std::max(1.0, std::abs(law.energy(F))));
  CHECK_NEAR((law.stress(Mat3(R * F)) - R * law.stress(F)).cwiseAbs().maxCoeff(), 0.0,
             1e-13 * std::max(1.0, law.stress(F).cwiseAbs().maxCoeff()));
}

// Deformation gradients: near identity, a large rotation of a stretch, and (for the laws
// defined there) an inverted one. det > 0 for the first two.
Mat3 near_identity() { return Mat3::Identity() + 0.3 * fixtures::random_matrix<Mat3>(); }
Mat3 rotated_stretch() {
  return fixtures::random_rotation() * Vec3(1.4, 0.9, 0.7).asDiagonal() * fixtures::random_rotation().transpose();
}
Mat3 inverted() {
  return fixtures::random_rotation() * Vec3(1.2, 0.8, -0.5).asDiagonal() * fixtures::random_rotation().transpose();
}

template <class Law>
void check_law(const Law& law, bool inversion_safe) {
  check_rest_state(law);
  std::vector<Mat3> cases = {near_identity(), near_identity(), rotated_stretch()};
  if (inversion_safe) cases.push_back(inverted());
  for (const Mat3& F : cases) {
    check_stress_is_energy_gradient<Law, 3>(law, F);
    check_tangent_is_stress_gradient<Law, 3>(law, F);
    check_rotation_invariance(law, F);
  }
}

}  // namespace

TEST(stvk_stress_and_tangent_are_derivatives) { check_law(StVK{lambda, mu}, true); }
TEST(stable_neo_hookean_stress_and_tangent_are_derivatives) { check_law(StableNeoHookean{lambda, mu}, true); }
TEST(fixed_corotated_stress_and_tangent_are_derivatives) { check_law(FixedCorotated{lambda, mu}, true); }

TEST(mooney_rivlin_stress_and_tangent_are_derivatives) {
  // C10, C01 both active, mu = 2 (C10 + C01) and bulk = lambda + 2 mu / 3 (the rest check).
  check_law(MooneyRivlin{0.4, 0.25, lambda + 2 * mu / 3}, false);
}

TEST(mooney_rivlin_is_undefined_under_inversion) {
  const MooneyRivlin law{0.4, 0.25, 3.0};
  CHECK(law.energy(inverted()) == std::numeric_limits<double>::infinity());
  CHECK(law.stress(inverted()).array().isNaN().all());
  CHECK(law.tangent(inverted()).array().isNaN().all());
}

TEST(stvk_membrane_stress_and_tangent_are_derivatives) {
  const StVK law{lambda, mu};
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix<double, 3, 2> F = fixtures::random_rotation().leftCols<2>();
    F += 0.3 * fixtures::random_matrix<Eigen::Matrix<double, 3, 2>>();
    check_stress_is_energy_gradient<StVK, 2>(law, F);
    check_tangent_is_stress_gradient<StVK, 2>(law, F);
  }
}

TEST(fixed_corotated_energy_is_the_distance_to_the_rotation) {
  // W = mu |F - R|^2 + lambda/2 (J - 1)^2 with R the polar rotation: for F = R S, S = diag(s),
  // W = mu sum (s_i - 1)^2 + lambda/2 (prod s_i - 1)^2.
  const Vec3 s(1.3, 0.8, 1.1);
  const Mat3 F = fixtures::random_rotation() * s.asDiagonal();
  const double expected = mu * (s.array() - 1).square().sum() + 0.5 * lambda * std::pow(s.prod() - 1, 2);
  CHECK_NEAR((FixedCorotated{lambda, mu}.energy(F)), expected, 1e-14);
}
