// Total-Lagrangian hyperelastic FEM with a constitutive law Law (StVK, StableNeoHookean,
// FixedCorotated, MooneyRivlin, ...; see corotate/materials/) on any element type: solids
// (Tet4, Hex8, Hex20) and membranes (Tri3). Each element keeps its law object, made from
// its region's material (law_parameters.hpp).
//
// Energy  E(x) = sum_e sum_q w_q W(F_q),   F_q = x_e G_q,  G_q = dN/dX at point q,
// forces  f = -dE/dx,  stiffness  K = d2E/dx2 (exact, symmetric; so tangent = stiffness).
// G_q and w_q come once from the rest shape with the element's stiffness rule (Tet4: one
// point, F = Ds Dm^-1; Hex8: 2x2x2; Hex20: 3x3x3), so at rest K equals the linear FEM
// stiffness exactly. The element stiffness is recomputed on each request rather than
// cached: a cache would cost 3N x 3N per element and explicit steps never need it.
//
// Membranes (elements whose reference coordinates span a plane, D = 2): F is 3 x 2, the
// Green strain 2 x 2, and a thin sheet carries no stress through its thickness, so the law
// gets the plane-stress Lame parameter lambda_ps = 2 lambda mu / (lambda + 2 mu)
// (= E nu / (1 - nu^2)); w = thickness x rest area. A flat membrane has no bending
// stiffness: static solves of a flat sheet need out-of-plane loads carried by tension.
#pragma once

#include <algorithm>
#include <limits>
#include <sstream>
#include <type_traits>
#include <vector>

#include "corotate/fem/element_kernel.hpp"
#include "corotate/materials/law_parameters.hpp"
#include "corotate/materials/stvk.hpp"
#include "corotate/models/hyperelastic_point.hpp"

namespace corotate {

template <class E, class Law>
class HyperelasticKernel {
 public:
  static constexpr int N = E::num_nodes;
  static constexpr int D = E::dim;
  using ElementType = E;
  using NodeMatrix = typename KernelTypes<E>::NodeMatrix;
  using Stiffness = typename KernelTypes<E>::Stiffness;
  using NodeScalars = typename KernelTypes<E>::NodeScalars;
  using Deformation = Eigen::Matrix<double, 3, D>;
  static constexpr const char* name = Law::name;
  static constexpr bool constant_stiffness = false;
  static constexpr bool forces_linear_given_frame = false;
  static constexpr bool has_geometric_stiffness = true;
  struct Element {
    QuadraturePoints<E> points;
    Law law;  // of the element's material
  };
  using Frame = NoFrame;
  using Cache = NoCache;

  HyperelasticKernel(const RegionMaterials& materials, const ModelOptions& options) : thickness_(options.thickness) {
    for (const Material& m : materials.materials) laws_.push_back(law_of_material<Law>(m, D == 2));
  }

  Element precompute(const NodeMatrix& X, Index e, int region) const {
    return {quadrature_points<E>(X, e, thickness_), laws_[region]};
  }
  Frame frame(const Element&, const NodeMatrix&, Cache&) const { return {}; }
  double volume_ratio(const Element& el, const Frame&, const NodeMatrix& x) const {
    if constexpr (D == 2) {
      return 1.0;  // a membrane has no volume to invert; it may fold freely
    } else {
      double smallest = std::numeric_limits<double>::infinity();
      for (const auto& p : el.points) smallest = std::min(smallest, Mat3(x * p.G).determinant());
      return smallest;
    }
  }
  double energy(const Element& el, const Frame&, const NodeMatrix& x) const {
    double total = 0;
    for (const auto& p : el.points) total += p.w * el.law.energy(Deformation(x * p.G));
    return total;
  }
  void forces(const Element& el, const Frame&, const NodeMatrix& x, NodeMatrix& f) const {
    f.setZero();
    for (const auto& p : el.points) add_point_forces<Law, N, D>(el.law, Deformation(x * p.G), p.G, p.w, f);
  }
  template <class Sink>
  void stiffness(const Element& el, const Frame&, const NodeMatrix& x, Sink& sink) const {
    Stiffness K = Stiffness::Zero();
    for (const auto& p : el.points) add_point_stiffness<Law, N, D>(el.law, Deformation(x * p.G), p.G, p.w, K);
    for (int a = 0; a < N; ++a)
      for (int b = a; b < N; ++b) sink.add(a, b, K.template block<3, 3>(3 * a, 3 * b));
  }
  bool tangent(const Element&, const Frame&, const NodeMatrix&, Stiffness&) const { return false; }  // = stiffness

  // k_ab = sum_q w_q G_a^T S G_b with S the second Piola-Kirchhoff stress at x; S = F^-1 P
  // for laws other than StVK, which needs det F > 0 (InvalidInput naming the element).
  void geometric_stiffness(const Element& el, const NodeMatrix& x, NodeScalars& k, Index e) const {
    k.setZero();
    for (const auto& p : el.points) {
      const Deformation F = x * p.G;
      Eigen::Matrix<double, D, D> S;
      if constexpr (std::is_same_v<Law, StVK>) {
        S = el.law.second_piola(F);
      } else if constexpr (D == 3) {
        const double J = F.determinant();
        if (!(J > 0)) {
          std::ostringstream msg;
          msg << "element " << e << " (" << E::name << ") is inverted or flat at these positions (det F = " << J
              << "), so its second Piola-Kirchhoff stress, and the geometric stiffness, are undefined";
          throw InvalidInput(msg.str());
        }
        S = F.inverse() * el.law.stress(F);
        S = 0.5 * (S + S.transpose()).eval();  // symmetric in exact arithmetic
      } else {
        throw InvalidInput(std::string("the geometric stiffness of '") + Law::name + "' membranes is not available");
      }
      k += point_geometric_stiffness<N, D>(S, p.G, p.w);
    }
  }

 private:
  std::vector<Law> laws_;  // by region
  double thickness_;
};

}  // namespace corotate
