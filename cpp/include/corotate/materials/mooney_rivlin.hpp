// Compressible Mooney-Rivlin in isochoric invariants (the "uncoupled" form of FEBio and
// Abaqus; Bonet & Wood, "Nonlinear Continuum Mechanics for Finite Element Analysis", 6.6):
//     W = C10 (I1b - 3) + C01 (I2b - 3) + bulk/2 (J - 1)^2,
//     I1b = J^-2/3 I1,  I2b = J^-4/3 I2,  I1 = tr C,  I2 = (I1^2 - C:C)/2,  C = F^T F,  J = det F.
// The isochoric invariants do not change under a pure volume change, so C10 and C01 carry
// the shear and the last term alone the volume. At rest the shear modulus is
// mu = 2 (C10 + C01) and the bulk modulus is `bulk`; with bulk >> mu the solid is nearly
// incompressible and, in uniaxial tension of stretch s, the nominal stress tends to
// P = 2 (s - s^-2) (C10 + C01 / s).
//
// Parameters: C10 > 0, C01 >= 0 (both non-negative keeps the energy convex in the isochoric
// stretches), bulk > 0. A material given by E and nu becomes the neo-Hookean member with
// the same small-strain moduli: C10 = mu/2, C01 = 0, bulk = lambda + 2 mu / 3.
//
// Derivatives by the chain rule through W(I1, I2, J):
//     P = W_1 dI1 + W_2 dI2 + W_J dJ,   dI1 = 2 F,  dI2 = 2 (I1 F - F C),  dJ = cof F,
//     dP/dF = W_1 d2I1 + W_2 d2I2 + W_J d2J + sum over a, b of W_ab dI_a dI_b^T,
// with d2I1 = 2 I, d2I2[dF] = 2 (2 (F:dF) F + I1 dF - dF C - F dF^T F - F F^T dF), d2J from
// determinant_derivatives.hpp, and W_11 = W_22 = W_12 = 0. Defined for J > 0 only (J^-2/3):
// at J <= 0 the energy is +inf (a line search backs away) and stress and tangent are NaN (a
// step fails loudly and restores its state), as for "neohookean_log".
#pragma once

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "corotate/materials/determinant_derivatives.hpp"
#include "corotate/materials/law_parameters.hpp"

namespace corotate {

struct MooneyRivlin {
  static constexpr const char* name = "mooney_rivlin";
  static constexpr LawParameter parameters[] = {
      positive("C10", "coefficient of the first isochoric invariant [Pa]"),
      non_negative("C01", "coefficient of the second isochoric invariant [Pa]"),
      positive("bulk", "bulk modulus [Pa]"),
  };
  double C10, C01, bulk;

  static MooneyRivlin from_parameters(const double* p) { return {p[0], p[1], p[2]}; }
  static std::vector<double> parameters_from_moduli(double lambda, double mu) {
    return {mu / 2, 0.0, lambda + 2 * mu / 3};
  }
  static std::pair<double, double> small_strain_moduli(const double* p) {
    const double mu = 2 * (p[0] + p[1]);
    return {p[2] - 2 * mu / 3, mu};
  }

  double energy(const Mat3& F) const {
    const double J = F.determinant();
    if (!(J > 0)) return std::numeric_limits<double>::infinity();
    const Mat3 C = F.transpose() * F;
    const double I1 = C.trace(), I2 = 0.5 * (I1 * I1 - C.squaredNorm()), a = std::pow(J, -2.0 / 3.0);
    return C10 * (a * I1 - 3) + C01 * (a * a * I2 - 3) + 0.5 * bulk * (J - 1) * (J - 1);
  }

  Mat3 stress(const Mat3& F) const {
    const Point p(*this, F);
    if (!p.defined) return Mat3::Constant(std::numeric_limits<double>::quiet_NaN());
    return p.W1 * p.dI1 + p.W2 * p.dI2 + p.WJ * p.dJ;
  }

  Eigen::Matrix<double, 9, 9> tangent(const Mat3& F) const {
    const Point p(*this, F);
    if (!p.defined) return Eigen::Matrix<double, 9, 9>::Constant(std::numeric_limits<double>::quiet_NaN());
    using Vec9 = Eigen::Matrix<double, 9, 1>;
    const Eigen::Map<const Vec9> d1(p.dI1.data()), d2(p.dI2.data()), dJ(p.dJ.data());
    Eigen::Matrix<double, 9, 9> A = p.WJ * determinant_hessian(F);
    A.noalias() += p.W1J * (d1 * dJ.transpose() + dJ * d1.transpose());
    A.noalias() += p.W2J * (d2 * dJ.transpose() + dJ * d2.transpose());
    A.noalias() += p.WJJ * dJ * dJ.transpose();
    A.diagonal().array() += 2 * p.W1;
    // W_2 d2I2, column i + 3 j for dF = e_i e_j^T.
    const Mat3 C = F.transpose() * F, B = F * F.transpose();
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        Mat3 d = (2 * F(i, j)) * F - F.col(j) * F.row(i);
        d(i, j) += p.I1;
        d.row(i) -= C.row(j);
        d.col(j) -= B.col(i);
        A.col(i + 3 * j) += (2 * p.W2) * Eigen::Map<const Vec9>(d.data());
      }
    return A;
  }

 private:
  // The invariants at F, their first derivatives and the derivatives of W in them.
  struct Point {
    bool defined;
    double I1, W1, W2, WJ, W1J, W2J, WJJ;
    Mat3 dI1, dI2, dJ;
    Point(const MooneyRivlin& law, const Mat3& F) {
      const double J = F.determinant();
      defined = J > 0;
      if (!defined) return;
      const Mat3 C = F.transpose() * F;
      I1 = C.trace();
      const double I2 = 0.5 * (I1 * I1 - C.squaredNorm()), a = std::pow(J, -2.0 / 3.0), b = a * a;
      dI1 = 2 * F;
      dI2 = 2 * (I1 * F - F * C);
      dJ = cofactor(F);
      W1 = law.C10 * a;
      W2 = law.C01 * b;
      WJ = (-2.0 / 3.0) * law.C10 * a * I1 / J - (4.0 / 3.0) * law.C01 * b * I2 / J + law.bulk * (J - 1);
      W1J = (-2.0 / 3.0) * law.C10 * a / J;
      W2J = (-4.0 / 3.0) * law.C01 * b / J;
      WJJ = (10.0 / 9.0) * law.C10 * a * I1 / (J * J) + (28.0 / 9.0) * law.C01 * b * I2 / (J * J) + law.bulk;
    }
  };
};

}  // namespace corotate
