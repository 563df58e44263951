// The co-rotational kernel for linear tets with an isotropic material: no K_e is stored.
// With a_i = R dN_i/dX the rotated stiffness blocks are
//     V (lambda a_i a_j^T + mu a_j a_i^T + mu (a_i . a_j) I),
// and the force is f_a = -V R sigma dN_a/dX with sigma the linear stress of the unrotated
// strain sym(R^T F) - I: identical to R K_e R^T and eq. (3), at a fraction of the memory
// traffic. Its tangent is exact (the derivative of the polar rotation included).
// Each element keeps its own lambda and mu (of its region's material), so a body of several
// materials runs the same code as a body of one.
#pragma once

#include <utility>
#include <vector>

#include "corotate/materials/determinant_derivatives.hpp"  // cross_matrix
#include "corotate/models/corotational_kernel.hpp"
#include "corotate/models/corotational_tet_batch.hpp"
#include "corotate/models/rotation_extraction.hpp"

namespace corotate {

template <>
class CorotationalKernel<Tet4> {
 public:
  using ElementType = Tet4;
  using NodeMatrix = Eigen::Matrix<double, 3, 4>;
  using Stiffness = Eigen::Matrix<double, 12, 12>;
  static constexpr const char* name = "corotational";
  static constexpr bool constant_stiffness = false;
  static constexpr bool forces_linear_given_frame = true;
  static constexpr bool has_geometric_stiffness = false;
  struct Element {
    Eigen::Matrix<double, 4, 3> G;  // dN/dX, constant on the tet
    double volume;
    double lambda, mu;  // Lame parameters of the element's material
  };
  struct Frame {
    Mat3 R;
    Mat3 F;  // at the frame's positions: energy and det F there need no second product
  };
  struct Cache {
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  };

  CorotationalKernel(const RegionMaterials& materials, const ModelOptions&) {
    for (const Material& m : materials.materials) moduli_.emplace_back(m.lame_lambda(), m.lame_mu());
  }

  Element precompute(const NodeMatrix& X, Index e, int region) const {
    const QuadraturePoints<Tet4> p = quadrature_points<Tet4>(X, e, 1.0);  // one point: the centre
    return {p[0].G, p[0].w, moduli_[region].first, moduli_[region].second};
  }
  double volume_ratio(const Element&, const Frame& fr, const NodeMatrix&) const { return fr.F.determinant(); }
  Frame frame(const Element& el, const NodeMatrix& x, Cache& cache) const {
    const Mat3 F = x * el.G;
    return {extract_rotation(F, cache.q), F};
  }
  // Sixteen rotations at once: their iterations run side by side (extract_rotations), which
  // at a normal step costs about a third of sixteen separate calls.
  static constexpr int frame_batch = kTetBatch;
  void frames(const Element* el, const NodeMatrix* x, Cache* cache, Frame* out, int count) const {
    Mat3 F[frame_batch], R[frame_batch];
    Eigen::Quaterniond q[frame_batch];
    for (int b = 0; b < count; ++b) {
      F[b].noalias() = x[b] * el[b].G;
      q[b] = cache[b].q;
    }
    extract_rotations(F, q, R, count);
    for (int b = 0; b < count; ++b) {
      cache[b].q = q[b];
      out[b] = {R[b], F[b]};
    }
  }
  using BatchElements = TetBatchElements;
  // The constants of count <= frame_batch consecutive elements, packed for sweep_batch.
  BatchElements pack_batch(const Element* el, int count) const {
    BatchElements out;
    for (int b = 0; b < frame_batch; ++b) {
      const int k = b < count ? b : 0;  // lanes past count repeat the first element
      for (int n = 0; n < 4; ++n)
        for (int i = 0; i < 3; ++i) out.G[n][i][b] = el[k].G(n, i);
      out.volume[b] = el[k].volume;
      out.lambda[b] = el[k].lambda;
      out.mu[b] = el[k].mu;
    }
    return out;
  }
  // The implicit step's sweep of count <= frame_batch elements at once: frames() at x, then
  // forces() at `at` (x, or the linearisation's y), scale times stiffness(), energy() and
  // volume_ratio() at x (corotational_tet_batch.hpp). The elements stay in lanes throughout:
  // positions gathered straight into the batch, F and R computed and used there, never
  // stored element by element (shuffling between the two layouts cost 12 % of the sweep at
  // 15,360 tets). nodes: the elements' node indices, 4 each; el: theirs from pack_batch.
  void sweep_batch(const BatchElements& el, const Nodes& x, const Nodes& at, const int* nodes, Cache* cache, int count,
                   double scale, ForceStiffnessBatch<4, frame_batch>& out) const {
    static_assert(frame_batch == kRotationLanes);
    TetBatchInput in;
    gather_tet_batch(el, x.data(), at.data(), nodes, count, in);
    Eigen::Quaterniond q[frame_batch];
    for (int b = 0; b < count; ++b) q[b] = cache[b].q;
    extract_rotations(in.F, q, in.R, count);
    for (int b = 0; b < count; ++b) cache[b].q = q[b];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int b = count; b < frame_batch; ++b) in.R[i][j][b] = in.R[i][j][0];
    corotational_tet_batch(in, scale, out);
  }
  double energy(const Element& el, const Frame& fr, const NodeMatrix&) const {  // at the frame's positions
    Mat3 strain = fr.R.transpose() * fr.F;
    strain = 0.5 * (strain + strain.transpose()).eval();
    strain.diagonal().array() -= 1.0;
    return 0.5 * el.volume * strain.cwiseProduct(stress(el, strain)).sum();
  }
  void forces(const Element& el, const Frame& fr, const NodeMatrix& x, NodeMatrix& f) const {
    const Mat3 P = el.volume * fr.R * stress(el, unrotated_strain(el, fr.R, x));  // f_a = -P dN_a/dX
    f.noalias() = -P * el.G.transpose();
  }
  template <class Sink>
  void stiffness(const Element& el, const Frame& fr, const NodeMatrix&, Sink& K) const {
    const Eigen::Matrix<double, 3, 4> a = fr.R * el.G.transpose();  // rotated gradients
    const double v = el.volume;
    for (int i = 0; i < 4; ++i)
      for (int j = i; j < 4; ++j) {
        Mat3 block = (v * el.lambda) * a.col(i) * a.col(j).transpose() + (v * el.mu) * a.col(j) * a.col(i).transpose();
        block.diagonal().array() += v * el.mu * a.col(i).dot(a.col(j));
        K.add(i, j, block);
      }
  }
  // Exact tangent. With P(F) = R sigma(sym(R^T F) - I) the element force is f_a = -V P g_a
  // (g_a = dN_a/dX). For the polar rotation R^T F = S stays symmetric, which fixes
  // dR = R [theta]x through (tr(S) I - S) theta = vee(W - W^T), W = R^T dF. Moving node b by
  // dx_b gives dF = dx_b g_b^T, W = y g_b^T with y = R^T dx_b, so theta = A_b y with
  //     A_b = H^-1 [g_b]x,   H = tr(S) I - S,
  // and dP = R ([theta]x sigma + dsigma), dsigma = sigma(sym(W - [theta]x S)). Collecting
  // the terms of -df_a = V dP g_a that are linear in y gives the block, in the element frame,
  //     K_ab = V ( N_a A_b + mu (g_a . g_b) I + mu g_b g_a^T + lambda g_a g_b^T ),
  //     N_a  = -[sigma g_a]x + mu ([S g_a]x - S [g_a]x),
  // and R K_ab R^T globally; without the N_a A_b term it is eq. (4)'s R K_e R^T.
  // Fills the blocks a <= b. Returns false where H is near singular (inverted elements).
  bool tangent(const Element& el, const Frame& fr, const NodeMatrix& x, Stiffness& K) const {
    const Mat3& R = fr.R;
    Mat3 S, H_inv;
    if (!polar_rotation_derivative(R, Mat3(x * el.G), S, H_inv)) return false;
    Mat3 strain = S;
    strain.diagonal().array() -= 1.0;
    const Mat3 sigma = stress(el, strain);
    const double lambda = el.lambda, mu = el.mu;
    const double v = el.volume;
    Mat3 A[4], N[4];
    for (int c = 0; c < 4; ++c) {
      const Vec3 g = el.G.row(c).transpose();
      A[c] = H_inv * cross_matrix(g);
      N[c] = mu * (cross_matrix(S * g) - S * cross_matrix(g)) - cross_matrix(sigma * g);
    }
    for (int a = 0; a < 4; ++a) {
      const Vec3 ga = el.G.row(a).transpose();
      for (int b = a; b < 4; ++b) {
        const Vec3 gb = el.G.row(b).transpose();
        Mat3 local = N[a] * A[b] + mu * gb * ga.transpose() + lambda * ga * gb.transpose();
        local.diagonal().array() += mu * ga.dot(gb);
        K.block<3, 3>(3 * a, 3 * b).noalias() = (v * R) * local * R.transpose();
      }
    }
    return true;
  }

 private:
  // sym(R^T F) - I at positions x.
  static Mat3 unrotated_strain(const Element& el, const Mat3& R, const NodeMatrix& x) {
    Mat3 strain = R.transpose() * (x * el.G);
    strain = 0.5 * (strain + strain.transpose()).eval();
    strain.diagonal().array() -= 1.0;
    return strain;
  }
  static Mat3 stress(const Element& el, const Mat3& strain) {
    Mat3 s = (2 * el.mu) * strain;
    s.diagonal().array() += el.lambda * strain.trace();
    return s;
  }

  std::vector<std::pair<double, double>> moduli_;  // (lambda, mu) by region
};

}  // namespace corotate
