// Element matrices of Tet4, Hex8 and Hex20: rigid motions cost no energy, a uniform strain
// costs exactly V e^T H e, the mass sums to rho V.
#include <array>
#include <cmath>
#include <type_traits>

#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

const Material material{2e6, 0.3, 1200.0};

// Reference node coordinates of element E (3 x N).
template <class E>
Eigen::Matrix<double, 3, E::num_nodes> reference_nodes() {
  Eigen::Matrix<double, 3, E::num_nodes> xi;
  for (int a = 0; a < E::num_nodes; ++a) {
    if constexpr (std::is_same_v<E, Tet4>) xi.col(a) = a == 0 ? Vec3(Vec3::Zero()) : Vec3(Vec3::Unit(a - 1));
    else xi.col(a) = E::node(a);
  }
  return xi;
}

// An affine image X = A xi + c of the reference element (a skewed parallelepiped or tet)
// and its exact volume |det A| * reference volume.
template <class E>
std::pair<Eigen::Matrix<double, 3, E::num_nodes>, double> affine_element() {
  Mat3 A;
  A << 0.9, 0.2, -0.1, 0.1, 1.3, 0.15, -0.05, 0.3, 0.7;
  const Vec3 c(0.4, -1.0, 2.0);
  const double reference_volume = std::is_same_v<E, Tet4> ? 1.0 / 6.0 : 8.0;
  return {(A * reference_nodes<E>()).colwise() + c, A.determinant() * reference_volume};
}

// The affine element with every node moved randomly by up to 5 % of its size.
template <class E>
Eigen::Matrix<double, 3, E::num_nodes> distorted_element() {
  auto X = affine_element<E>().first;
  return X + 0.05 * fixtures::random_matrix<Eigen::Matrix<double, 3, E::num_nodes>>();
}

template <class E>
using Dofs = Eigen::Matrix<double, 3 * E::num_nodes, 1>;

template <class E>
Dofs<E> flatten(const Eigen::Matrix<double, 3, E::num_nodes>& u) {
  return Eigen::Map<const Dofs<E>>(u.data());
}

template <class E>
void check_rigid_modes_are_annihilated() {
  const auto X = distorted_element<E>();
  const auto m = compute_element_matrices<E>(X, material, 0);
  const double k_norm = m.stiffness.norm();
  CHECK((m.stiffness - m.stiffness.transpose()).norm() == 0.0);
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Matrix<double, 3, E::num_nodes> u = Eigen::Matrix<double, 3, E::num_nodes>::Zero();
    u.row(axis).setOnes();  // translation
    const Dofs<E> t = flatten<E>(u);
    // K t is a sum of terms of size |K| |t| that cancel exactly in exact arithmetic.
    CHECK_NEAR((m.stiffness * t).norm(), 0.0, 1e-13 * E::num_nodes * k_norm * t.norm());
    for (int a = 0; a < E::num_nodes; ++a) u.col(a) = Vec3::Unit(axis).cross(X.col(a));  // rotation w x X
    const Dofs<E> r = flatten<E>(u);
    CHECK_NEAR((m.stiffness * r).norm(), 0.0, 1e-13 * E::num_nodes * k_norm * r.norm());
  }
  // Not singular beyond the six rigid modes: the seventh smallest eigenvalue is clearly positive.
  const Eigen::SelfAdjointEigenSolver<typename ElementMatrices<E>::Stiffness> eig(m.stiffness);
  CHECK(eig.eigenvalues()(6) > 1e-6 * eig.eigenvalues().maxCoeff());
  CHECK(eig.eigenvalues()(0) > -1e-12 * eig.eigenvalues().maxCoeff());
}

template <class E>
void check_uniform_strain_energy_and_mass() {
  const auto [X, volume] = affine_element<E>();
  const auto m = compute_element_matrices<E>(X, material, 0);
  CHECK_NEAR(m.volume, volume, 1e-13 * volume);

  // u = G X with G symmetric: B u is the constant strain e (Voigt, engineering shear), so
  // u^T K u = V e^T H e exactly (the quadrature weights times det J sum to V).
  Mat3 G = fixtures::random_matrix<Mat3>();
  G = 0.5 * (G + G.transpose()).eval();
  const Dofs<E> u = flatten<E>(G * X);
  Eigen::Matrix<double, 6, 1> e;
  e << G(0, 0), G(1, 1), G(2, 2), 2 * G(1, 2), 2 * G(0, 2), 2 * G(0, 1);
  const double expected = volume * e.dot(material.elasticity_matrix() * e);
  CHECK_NEAR(u.dot(m.stiffness * u), expected, 1e-12 * expected);

  const double total = material.density * volume;
  CHECK_NEAR(m.mass.sum(), total, 1e-13 * total);
  CHECK_NEAR(m.lumped_mass.sum(), total, 1e-13 * total);
  CHECK((m.lumped_mass.array() > 0).all());
  // The consistent mass is symmetric positive definite.
  CHECK((m.mass - m.mass.transpose()).norm() <= 1e-15 * m.mass.norm());
  CHECK(Eigen::LLT<Eigen::Matrix<double, E::num_nodes, E::num_nodes>>(m.mass).info() == Eigen::Success);
}

// Volume of an element by integrating det J independently of the library's quadrature: the
// 3-point Gauss rule per direction is exact for det J of Hex8 (degree <= 2 per direction)
// and Hex20 (degree <= 5); a linear tet's volume is det(X1 - X0, X2 - X0, X3 - X0) / 6.
template <class E>
double exact_volume(const Eigen::Matrix<double, 3, E::num_nodes>& X) {
  if constexpr (std::is_same_v<E, Tet4>) {
    Mat3 D;
    for (int s = 0; s < 3; ++s) D.col(s) = X.col(s + 1) - X.col(0);
    return D.determinant() / 6;
  } else {
    const double x[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    double volume = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          volume += w[i] * w[j] * w[k] * (X * E::shape_gradient(Vec3(x[i], x[j], x[k]))).determinant();
    return volume;
  }
}

template <class E>
void check_distorted_mass_sums_to_rho_v() {
  // On a curved (non-affine) element too: sum_ab m_ab = rho integral (sum_a N_a)^2 dV = rho V.
  const auto X = distorted_element<E>();
  const auto m = compute_element_matrices<E>(X, material, 0);
  const double volume = exact_volume<E>(X), total = material.density * volume;
  CHECK(volume > 0);
  CHECK_NEAR(m.volume, volume, 1e-13 * volume);
  CHECK_NEAR(m.mass.sum(), total, 1e-13 * total);
  CHECK_NEAR(m.lumped_mass.sum(), total, 1e-13 * total);
}

}  // namespace

TEST(tet4_stiffness_annihilates_rigid_motions) { check_rigid_modes_are_annihilated<Tet4>(); }
TEST(hex8_stiffness_annihilates_rigid_motions) { check_rigid_modes_are_annihilated<Hex8>(); }
TEST(hex20_stiffness_annihilates_rigid_motions) { check_rigid_modes_are_annihilated<Hex20>(); }

TEST(tet4_uniform_strain_energy_and_mass) { check_uniform_strain_energy_and_mass<Tet4>(); }
TEST(hex8_uniform_strain_energy_and_mass) { check_uniform_strain_energy_and_mass<Hex8>(); }
TEST(hex20_uniform_strain_energy_and_mass) { check_uniform_strain_energy_and_mass<Hex20>(); }

TEST(tet4_distorted_mass_sums_to_rho_v) { check_distorted_mass_sums_to_rho_v<Tet4>(); }
TEST(hex8_distorted_mass_sums_to_rho_v) { check_distorted_mass_sums_to_rho_v<Hex8>(); }
TEST(hex20_distorted_mass_sums_to_rho_v) { check_distorted_mass_sums_to_rho_v<Hex20>(); }

TEST(tet4_volume_is_the_determinant_over_six) {
  Eigen::Matrix<double, 3, 4> X;
  X << 0, 2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 4;
  CHECK_NEAR(compute_element_matrices<Tet4>(X, material, 0).volume, 4.0, 1e-15 * 4);
}

TEST(inverted_and_degenerate_elements_are_rejected) {
  Eigen::Matrix<double, 3, 4> X;
  X << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  Eigen::Matrix<double, 3, 4> inverted = X;
  inverted.col(1).swap(inverted.col(2));
  CHECK_THROWS(compute_element_matrices<Tet4>(inverted, material, 7), InvalidInput);
  Eigen::Matrix<double, 3, 4> flat = X;
  flat(2, 3) = 0;  // all four nodes in z = 0
  CHECK_THROWS(compute_element_matrices<Tet4>(flat, material, 7), InvalidInput);
}

// Hex8::grid_cube: on a grid with node (i, j, k) at (i, j, k) and any numbering, node a of
// cube (i, j, k) sits at the cube's centre plus half of the reference node a.
TEST(hex8_grid_cube_follows_the_reference_node_order) {
  const int n = 4;
  auto id = [&](int i, int j, int k) { return (k * n + j) * n + i; };
  auto position = [&](int v) { return Vec3(v % n, (v / n) % n, v / (n * n)); };
  const std::array<int, 8> cube = Hex8::grid_cube(id, 1, 2, 0);
  for (int a = 0; a < 8; ++a)
    CHECK_NEAR((position(cube[a]) - (Vec3(1.5, 2.5, 0.5) + 0.5 * Hex8::node(a))).norm(), 0.0, 0.0);
}
