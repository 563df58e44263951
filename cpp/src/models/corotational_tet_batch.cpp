#include "corotate/models/corotational_tet_batch.hpp"

#include <type_traits>

#include "corotate/cpu_clones.hpp"

namespace corotate {

namespace {
constexpr int B = kTetBatch;

// sigma = 2 mu strain + lambda tr(strain) I of strain = sym(R^T F) - I, lane by lane.
COROTATE_CLONE_INLINE void stress(const double (&R)[3][3][B], const double (&F)[3][3][B], const double (&lambda)[B],
                                  const double (&mu)[B], double (&sigma)[3][3][B]) {
  double C[3][3][B];
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l)
      for (int b = 0; b < B; ++b)
        C[k][l][b] = R[0][k][b] * F[0][l][b] + R[1][k][b] * F[1][l][b] + R[2][k][b] * F[2][l][b];
  for (int b = 0; b < B; ++b) {
    const double e00 = C[0][0][b] - 1, e11 = C[1][1][b] - 1, e22 = C[2][2][b] - 1;
    const double trace = lambda[b] * (e00 + e11 + e22), twice_mu = 2 * mu[b];
    sigma[0][0][b] = twice_mu * e00 + trace;
    sigma[1][1][b] = twice_mu * e11 + trace;
    sigma[2][2][b] = twice_mu * e22 + trace;
    sigma[0][1][b] = sigma[1][0][b] = mu[b] * (C[0][1][b] + C[1][0][b]);
    sigma[0][2][b] = sigma[2][0][b] = mu[b] * (C[0][2][b] + C[2][0][b]);
    sigma[1][2][b] = sigma[2][1][b] = mu[b] * (C[1][2][b] + C[2][1][b]);
  }
}
}  // namespace

COROTATE_CPU_CLONES void gather_tet_batch(const TetBatchElements& elements, const double* x, const double* at,
                                          const int* nodes, int count, TetBatchInput& in) {
  in.elements = &elements;
  alignas(64) double xs[4][3][B];
  for (int b = 0; b < B; ++b) {
    const int k = b < count ? b : 0;
    for (int n = 0; n < 4; ++n) {
      const double* xn = x + 3 * Index(nodes[4 * k + n]);
      const double* yn = at + 3 * Index(nodes[4 * k + n]);
      for (int i = 0; i < 3; ++i) {
        xs[n][i][b] = xn[i];
        in.y[n][i][b] = yn[i];
      }
    }
  }
  const auto& G = elements.G;
  for (int i = 0; i < 3; ++i)  // F = x G
    for (int j = 0; j < 3; ++j)
      for (int b = 0; b < B; ++b)
        in.F[i][j][b] =
            xs[0][i][b] * G[0][j][b] + xs[1][i][b] * G[1][j][b] + xs[2][i][b] * G[2][j][b] + xs[3][i][b] * G[3][j][b];
}

COROTATE_CPU_CLONES void corotational_tet_batch(const TetBatchInput& in, double scale,
                                                ForceStiffnessBatch<4, kTetBatch>& out) {
  const auto& G = in.elements->G;
  const auto& volume = in.elements->volume;
  const auto& lambda = in.elements->lambda;
  const auto& mu = in.elements->mu;
  // Forces: F = y G, strain = sym(R^T F) - I, sigma = 2 mu strain + lambda tr(strain) I,
  // f_a = P g_a with P = -V R sigma.
  alignas(64) double F[3][3][B];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      for (int b = 0; b < B; ++b)
        F[i][k][b] = in.y[0][i][b] * G[0][k][b] + in.y[1][i][b] * G[1][k][b] + in.y[2][i][b] * G[2][k][b] +
                     in.y[3][i][b] * G[3][k][b];
  alignas(64) double sigma[3][3][B];
  stress(in.R, F, lambda, mu, sigma);
  alignas(64) double P[3][3][B];  // -V R sigma
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      for (int b = 0; b < B; ++b)
        P[i][k][b] = -volume[b] *
                     (in.R[i][0][b] * sigma[0][k][b] + in.R[i][1][b] * sigma[1][k][b] + in.R[i][2][b] * sigma[2][k][b]);
  for (int n = 0; n < 4; ++n)
    for (int i = 0; i < 3; ++i)
      for (int b = 0; b < B; ++b)
        out.f[n][i][b] = P[i][0][b] * G[n][0][b] + P[i][1][b] * G[n][1][b] + P[i][2][b] * G[n][2][b];

  // Energy V/2 strain : sigma and det F at the frame's positions. With strain e = sym(C) - I,
  // C = R^T F, and sigma = 2 mu e + lambda tr(e) I: e : sigma = 2 mu e : e + lambda tr(e)^2,
  // from C alone (no second stress tensor). Loops over the lanes innermost, like the rest:
  // the same sums written per element (C in a local 3 x 3 array) compiled to scalar code,
  // a sixth of this function's time.
  alignas(64) double C[3][3][B];
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l)
      for (int b = 0; b < B; ++b)
        C[k][l][b] = in.R[0][k][b] * in.F[0][l][b] + in.R[1][k][b] * in.F[1][l][b] + in.R[2][k][b] * in.F[2][l][b];
  for (int b = 0; b < B; ++b) {
    const double e00 = C[0][0][b] - 1, e11 = C[1][1][b] - 1, e22 = C[2][2][b] - 1, trace = e00 + e11 + e22;
    const double s01 = C[0][1][b] + C[1][0][b], s02 = C[0][2][b] + C[2][0][b],
                 s12 = C[1][2][b] + C[2][1][b];  // twice e_ij
    const double contraction = 2 * mu[b] * (e00 * e00 + e11 * e11 + e22 * e22) +
                               mu[b] * (s01 * s01 + s02 * s02 + s12 * s12) + lambda[b] * trace * trace;
    out.energy[b] = 0.5 * volume[b] * contraction;
    const auto& F = in.F;
    out.volume_ratio[b] = F[0][0][b] * (F[1][1][b] * F[2][2][b] - F[1][2][b] * F[2][1][b]) -
                          F[0][1][b] * (F[1][0][b] * F[2][2][b] - F[1][2][b] * F[2][0][b]) +
                          F[0][2][b] * (F[1][0][b] * F[2][1][b] - F[1][1][b] * F[2][0][b]);
  }

  if (!out.stiffness) return;
  // Rotated gradients a_i = R g_i.
  alignas(64) double a[4][3][B];
  for (int i = 0; i < 4; ++i)
    for (int r = 0; r < 3; ++r)
      for (int b = 0; b < B; ++b)
        a[i][r][b] = in.R[r][0][b] * G[i][0][b] + in.R[r][1][b] * G[i][1][b] + in.R[r][2][b] * G[i][2][b];

  // Blocks (i, j), i <= j: with u = a_i a_j^T, lambda V u + mu V u^T + mu V (a_i . a_j) I.
  // Diagonal blocks come out exactly symmetric (u is). For a float32 system they are computed
  // in float32 from a rounded to float32 (twice the lanes per instruction; the blocks are
  // rounded to float32 anyway, and the extra rounding of a is of the same size).
  auto blocks = [&](const auto& g, auto& K) {
    using Value = std::remove_reference_t<decltype(K[0][0][0])>;
    Value vl[B], vm[B];
    for (int b = 0; b < B; ++b) vl[b] = Value(scale * volume[b] * lambda[b]), vm[b] = Value(scale * volume[b] * mu[b]);
    int p = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i; j < 4; ++j, ++p)
        for (int b = 0; b < B; ++b) {
          const Value d = vm[b] * (g[i][0][b] * g[j][0][b] + g[i][1][b] * g[j][1][b] + g[i][2][b] * g[j][2][b]);
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
              K[p][3 * r + c][b] =
                  vl[b] * (g[i][r][b] * g[j][c][b]) + vm[b] * (g[j][r][b] * g[i][c][b]) + (r == c ? d : Value(0));
        }
  };
  if (out.single) {
    alignas(64) float a_single[4][3][B];
    for (int i = 0; i < 4; ++i)
      for (int r = 0; r < 3; ++r)
        for (int b = 0; b < B; ++b) a_single[i][r][b] = float(a[i][r][b]);
    blocks(a_single, out.K_single);
  } else {
    blocks(a, out.K);
  }
}

}  // namespace corotate
