// The inertial loads of a moving frame, split into twelve unit load cases, so that the
// geometric stiffness they cause (the paper's eqs 7-8, SIMPACK's load cases) is precomputed
// once per case and combined per step: K_geo = sum_c coefficient_c K_c.
//
// A node at u in the frame (origin acceleration a, angular velocity omega and acceleration
// alpha, all in the frame; g the gravity in the frame) feels the body force per unit mass
//
//   b(u) = -(a - g) - alpha x u - omega x (omega x u),
//   omega x (omega x u) = omega (omega . u) - |omega|^2 u,
//
// linear in the twelve coefficients below; with u = X (the rest positions: the stress of the
// deformation's own inertia is of higher order) the unit fields are, case by case:
//
//   0-2   omega_a^2                    X - e_a X_a             (centrifugal)
//   3-5   omega_0 omega_1, omega_0 omega_2, omega_1 omega_2:   -(e_a X_b + e_b X_a)
//   6-8   alpha_a                      -e_a x X                (Euler)
//   9-11  (a - g)_a                    -e_a                    (translation and gravity)
//
// corotate.modal.inertial_load_fields builds the same fields on the Python side (a test
// checks that the two agree).
#pragma once

#include <array>

#include "corotate/common.hpp"

namespace corotate {

constexpr int kInertialLoadCases = 12;

// The axis pairs (a, b) of the centrifugal cases 0-5, coefficient omega_a omega_b; also the
// order of a symmetric 3 x 3 tensor's six entries (xx, yy, zz, xy, xz, yz).
constexpr int kSymmetricPairs[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};

inline std::array<double, kInertialLoadCases> inertial_load_coefficients(const Vec3& omega, const Vec3& alpha,
                                                                         const Vec3& acceleration_minus_gravity) {
  return {omega[0] * omega[0],
          omega[1] * omega[1],
          omega[2] * omega[2],
          omega[0] * omega[1],
          omega[0] * omega[2],
          omega[1] * omega[2],
          alpha[0],
          alpha[1],
          alpha[2],
          acceleration_minus_gravity[0],
          acceleration_minus_gravity[1],
          acceleration_minus_gravity[2]};
}

}  // namespace corotate
