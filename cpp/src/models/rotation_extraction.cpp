#include "corotate/models/rotation_extraction.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "corotate/cpu_clones.hpp"

namespace corotate {

Mat3 polar_rotation_svd(const Mat3& F) {
  Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU();
  const Mat3& V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(2) *= -1;  // smallest singular value flips
  return U * V.transpose();
}

namespace {

constexpr int kMaxIterations = 20;
constexpr double kConvergedStep = 1e-6;  // quadratic: the remaining error is ~1e-12
constexpr double kRoughStep = 1e-3;      // extract_rotations_roughly's: ~1e-6

// W problems side by side, structure of arrays: A = F / |F| (row-major, a[3 i + j][lane]),
// the quaternion (w, x, y, z) and the squared angle of the last step.
template <int W>
struct Lanes {
  double a[9][W];
  double q[4][W];
  double step2[W];
};

// Below this angle in every lane, an iteration's step needs no trust region and the
// quaternion's normalisation a series instead of a square root and a division (the divider
// is what an iteration waits for otherwise: five divisions and square roots per lane against
// about 150 multiply-adds).
constexpr double kSmallStep = 5e-2;

// One iteration for every lane, branch-free so that the compiler vectorises it across lanes:
// the W dependency chains (each a long serial chain of products and a division) then overlap
// instead of waiting on each other.
//
// The polar rotation maximises tr(R^T F) over rotations. With R = exp([w]) R_c and
// B = F R_c^T, that objective is, to second order in w,
//     tr(B) + g.w - 1/2 w^T (tr(B) I - sym(B)) w,   g = sum_i r_i x f_i,
// where r_i, f_i are the columns of R_c and F. Mueller et al. 2016 step along g scaled by
// 1/tr(B), which converges linearly (rate 1/3 near a rotation). Taking the full Newton step
// w = (tr(B) I - sym(B))^-1 g converges quadratically: from the previous step's rotation,
// two or three iterations reach round-off. Where that Hessian is not positive definite (far
// from the answer) the Mueller step is the safe choice. The step is applied as the unit
// quaternion (1, w/2) / |(1, w/2)|: a rotation about w by 2 atan(|w|/2) = |w| - |w|^3/12 + ...,
// which keeps the convergence quadratic without a sine or cosine.
template <int W>
COROTATE_CLONE_INLINE void newton_iteration(Lanes<W>& L) {
  double w[3][W];
  int small = 0;
  for (int l = 0; l < W; ++l) {
    const double qw = L.q[0][l], qx = L.q[1][l], qy = L.q[2][l], qz = L.q[3][l];
    // R(q), row-major.
    const double r00 = 1 - 2 * (qy * qy + qz * qz), r01 = 2 * (qx * qy - qz * qw), r02 = 2 * (qx * qz + qy * qw);
    const double r10 = 2 * (qx * qy + qz * qw), r11 = 1 - 2 * (qx * qx + qz * qz), r12 = 2 * (qy * qz - qx * qw);
    const double r20 = 2 * (qx * qz - qy * qw), r21 = 2 * (qy * qz + qx * qw), r22 = 1 - 2 * (qx * qx + qy * qy);
    const double a00 = L.a[0][l], a01 = L.a[1][l], a02 = L.a[2][l];
    const double a10 = L.a[3][l], a11 = L.a[4][l], a12 = L.a[5][l];
    const double a20 = L.a[6][l], a21 = L.a[7][l], a22 = L.a[8][l];
    // g = sum over columns c of R.col(c) x A.col(c).
    const double gx = (r10 * a20 - r20 * a10) + (r11 * a21 - r21 * a11) + (r12 * a22 - r22 * a12);
    const double gy = (r20 * a00 - r00 * a20) + (r21 * a01 - r01 * a21) + (r22 * a02 - r02 * a22);
    const double gz = (r00 * a10 - r10 * a00) + (r01 * a11 - r11 * a01) + (r02 * a12 - r12 * a02);
    // B = A R^T.
    const double b00 = a00 * r00 + a01 * r01 + a02 * r02, b01 = a00 * r10 + a01 * r11 + a02 * r12;
    const double b02 = a00 * r20 + a01 * r21 + a02 * r22, b10 = a10 * r00 + a11 * r01 + a12 * r02;
    const double b11 = a10 * r10 + a11 * r11 + a12 * r12, b12 = a10 * r20 + a11 * r21 + a12 * r22;
    const double b20 = a20 * r00 + a21 * r01 + a22 * r02, b21 = a20 * r10 + a21 * r11 + a22 * r12;
    const double b22 = a20 * r20 + a21 * r21 + a22 * r22;
    const double trace = b00 + b11 + b22;
    // H = tr(B) I - sym(B), solved by its adjugate when its leading minors say it is
    // positive definite (a 3x3 LLT costs more and tells the same).
    const double h00 = trace - b00, h11 = trace - b11, h22 = trace - b22;
    const double h01 = -0.5 * (b01 + b10), h02 = -0.5 * (b02 + b20), h12 = -0.5 * (b12 + b21);
    const double c00 = h11 * h22 - h12 * h12, c01 = h02 * h12 - h01 * h22, c02 = h01 * h12 - h02 * h11;
    const double c11 = h00 * h22 - h02 * h02, c12 = h01 * h02 - h00 * h12, c22 = h00 * h11 - h01 * h01;
    const double det = h00 * c00 + h01 * c01 + h02 * c02;
    // (Bitwise & instead of &&, and one division of whichever denominator: no branch.)
    const bool newton = (h00 > 0) & (c22 > 0) & (det > 0);
    const double inv = 1 / (newton ? det : std::abs(trace) + 1e-9);
    const double wx = (newton ? c00 * gx + c01 * gy + c02 * gz : gx) * inv;
    const double wy = (newton ? c01 * gx + c11 * gy + c12 * gz : gy) * inv;
    const double wz = (newton ? c02 * gx + c12 * gy + c22 * gz : gz) * inv;
    w[0][l] = wx, w[1][l] = wy, w[2][l] = wz;
    const double step2 = wx * wx + wy * wy + wz * wz;
    L.step2[l] = step2;
    small += step2 < kSmallStep * kSmallStep;  // (false for NaN)
  }
  if (small == W) {
    // q <- (1, d) q with d = w / 2, normalised by the series of 1 / sqrt(1 + e), e = |q|^2 - 1
    // <= |d|^2 + round-off <= 6.25e-4: its terms to e^4 leave 63/256 e^5 < 3e-17.
    for (int l = 0; l < W; ++l) {
      const double qw = L.q[0][l], qx = L.q[1][l], qy = L.q[2][l], qz = L.q[3][l];
      const double dx = 0.5 * w[0][l], dy = 0.5 * w[1][l], dz = 0.5 * w[2][l];
      const double nw = qw - (dx * qx + dy * qy + dz * qz);
      const double nx = qx + dx * qw + (dy * qz - dz * qy);
      const double ny = qy + dy * qw + (dz * qx - dx * qz);
      const double nz = qz + dz * qw + (dx * qy - dy * qx);
      const double e = (nw * nw + nx * nx + ny * ny + nz * nz) - 1;
      const double s = 1 - e * (0.5 - e * (0.375 - e * (0.3125 - e * 0.2734375)));
      L.q[0][l] = nw * s, L.q[1][l] = nx * s, L.q[2][l] = ny * s, L.q[3][l] = nz * s;
    }
    return;
  }
  for (int l = 0; l < W; ++l) {
    // Trust region: at most one radian per iteration. A non-finite step leaves q as it was
    // and reports an infinite angle (the caller then falls back to the SVD).
    const double step2 = L.step2[l];
    const bool finite = step2 <= std::numeric_limits<double>::max();
    const double half = finite ? 0.5 / std::max(std::sqrt(step2), 1.0) : 0.0;
    const double qw = L.q[0][l], qx = L.q[1][l], qy = L.q[2][l], qz = L.q[3][l];
    const double dx = half * w[0][l], dy = half * w[1][l], dz = half * w[2][l];
    // q <- (1, d) q, then normalised.
    const double nw = qw - (dx * qx + dy * qy + dz * qz);
    const double nx = qx + dx * qw + (dy * qz - dz * qy);
    const double ny = qy + dy * qw + (dz * qx - dx * qz);
    const double nz = qz + dz * qw + (dx * qy - dy * qx);
    const double s = 1 / std::sqrt(nw * nw + nx * nx + ny * ny + nz * nz);
    L.q[0][l] = nw * s, L.q[1][l] = nx * s, L.q[2][l] = ny * s, L.q[3][l] = nz * s;
    L.step2[l] = finite ? step2 : std::numeric_limits<double>::infinity();
  }
}

// Loads F and q into the lanes, F scaled to unit norm. A lane whose F is zero or not finite
// gets the identity (harmless) and ok = false: the rotation of its q is then the answer.
// F(k, i, j): entry (i, j) of problem k.
template <int W, class FEntry>
COROTATE_CLONE_INLINE void load_lanes(Lanes<W>& L, bool* ok, const FEntry& F, const Eigen::Quaterniond* q, int n) {
  if (n == W) {  // (a full batch: plain copies, vectorised where F is laid out by lanes)
    for (int c = 0; c < 9; ++c)
      for (int l = 0; l < W; ++l) L.a[c][l] = F(l, c / 3, c % 3);
  } else {
    for (int l = 0; l < W; ++l) {
      const int k = l < n ? l : 0;  // lanes past n repeat the first problem
      for (int c = 0; c < 9; ++c) L.a[c][l] = F(k, c / 3, c % 3);
    }
  }
  for (int l = 0; l < W; ++l) {
    const int k = l < n ? l : 0;
    L.q[0][l] = q[k].w(), L.q[1][l] = q[k].x(), L.q[2][l] = q[k].y(), L.q[3][l] = q[k].z();
  }
  double scale[W];
  for (int l = 0; l < W; ++l) {
    double s2 = 0;
    for (int c = 0; c < 9; ++c) s2 += L.a[c][l] * L.a[c][l];
    const bool good = (s2 > 0) & (s2 <= std::numeric_limits<double>::max());  // false for NaN
    const double inverse = 1 / std::sqrt(s2);
    scale[l] = good ? inverse : 0.0;
    ok[l] = good;
  }
  for (int c = 0; c < 9; ++c)
    for (int l = 0; l < W; ++l) {
      const double identity = (c % 4 == 0) ? 1.0 : 0.0;
      L.a[c][l] = ok[l] ? L.a[c][l] * scale[l] : identity;
    }
}

// R(q) of every lane (unit quaternions).
template <int W>
COROTATE_CLONE_INLINE void lane_rotations(const Lanes<W>& L, double (&r)[9][W]) {
  for (int l = 0; l < W; ++l) {
    const double qw = L.q[0][l], qx = L.q[1][l], qy = L.q[2][l], qz = L.q[3][l];
    r[0][l] = 1 - 2 * (qy * qy + qz * qz), r[1][l] = 2 * (qx * qy - qz * qw), r[2][l] = 2 * (qx * qz + qy * qw);
    r[3][l] = 2 * (qx * qy + qz * qw), r[4][l] = 1 - 2 * (qx * qx + qz * qz), r[5][l] = 2 * (qy * qz - qx * qw);
    r[6][l] = 2 * (qx * qz - qy * qw), r[7][l] = 2 * (qy * qz + qx * qw), r[8][l] = 1 - 2 * (qx * qx + qy * qy);
  }
}

template <int W>
COROTATE_CLONE_INLINE Eigen::Quaterniond lane_quaternion(const Lanes<W>& L, int l) {
  return Eigen::Quaterniond(L.q[0][l], L.q[1][l], L.q[2][l], L.q[3][l]);
}

// The batched sweep's lockstep iterations: one, then more while a lane still moves (two for a
// warm start that moved less than ~1e-3 rad since the last call, a slowly turning body; one
// for a batch at rest), up to kMaxLockstepIterations (a body that turns fast: three reach
// ~0.03 rad), since one more batched iteration costs about what one lane costs alone; the
// rest finish one by one.
constexpr int kLockstepIterations = 1;
constexpr int kMaxLockstepIterations = 4;
// Sixteen lanes, all the sweep hands over at once (kRotationLanes): an iteration is a long
// chain of dependent operations, so what bounds it is latency, and four vectors of lanes in
// flight hide more of it than two (8 -> 16 lanes: 34.6 -> 26.5 ns per element in
// `--scenario rotations`; 512-bit vectors changed nothing). Fewer divisions did pay once the
// rest was lean (kSmallStep; docs/notes/performance.md).
constexpr int kBatch = 16;
static_assert(kBatch == kRotationLanes, "a sweep's batch of rotations is one lockstep batch, stored lane for lane");

// Whether a lane of the first n still moves (a finite last step of `converged` or more).
template <int W>
COROTATE_CLONE_INLINE bool any_lane_moving(const Lanes<W>& L, const bool* ok, int n, double converged) {
  bool moving = false;
  const double converged2 = converged * converged;
  for (int l = 0; l < n; ++l)
    moving |= ok[l] & (L.step2[l] >= converged2) & (L.step2[l] <= std::numeric_limits<double>::max());
  return moving;
}

// How far extract_batches iterates: at least `lockstep` iterations, then on while a lane's
// last step turned `converged` radians or more (the error left is about its square).
struct Accuracy {
  int lockstep;
  double converged;
};
constexpr Accuracy kRoundOff{kLockstepIterations, kConvergedStep};

}  // namespace

Mat3 extract_rotation(const Mat3& F, Eigen::Quaterniond& q) {
  Lanes<1> L;
  bool ok;
  load_lanes(L, &ok, [&F](int, int i, int j) { return F(i, j); }, &q, 1);
  if (!ok) return q.toRotationMatrix();
  for (int it = 0; it < kMaxIterations; ++it) {
    newton_iteration(L);
    if (!(L.step2[0] <= std::numeric_limits<double>::max())) break;
    q = lane_quaternion(L, 0);
    if (L.step2[0] < kConvergedStep * kConvergedStep) return q.toRotationMatrix();
  }
  const Mat3 R = polar_rotation_svd(F);
  q = Eigen::Quaterniond(R);
  return R;
}

namespace {

// The batched iterations on problems [0, count), kBatch at a time. F(k, i, j) reads entry
// (i, j) of problem k, store(k, r, stride) takes its rotation as nine row-major values
// r[c * stride], store_batch(first, r) a whole batch's that all converged (r[9][kBatch]),
// fallback(k) solves problem k alone (those that did not converge).
template <class FEntry, class Store, class StoreBatch, class Fallback>
COROTATE_CLONE_INLINE void extract_batches(const FEntry& F, Eigen::Quaterniond* q, const Store& store,
                                           const StoreBatch& store_batch, const Fallback& fallback, int count,
                                           Accuracy accuracy = kRoundOff) {
  for (int first = 0; first < count; first += kBatch) {
    const int n = std::min(kBatch, count - first);
    Lanes<kBatch> L;
    bool ok[kBatch];
    load_lanes(L, ok, [&](int k, int i, int j) { return F(first + k, i, j); }, q + first, n);
    int it = 0;
    for (; it < accuracy.lockstep; ++it) newton_iteration(L);
    for (; it < kMaxLockstepIterations && any_lane_moving(L, ok, n, accuracy.converged); ++it) newton_iteration(L);
    double r[9][kBatch];
    lane_rotations(L, r);
    const double converged2 = accuracy.converged * accuracy.converged;
    int done = 0;
    for (int l = 0; l < kBatch; ++l) done += ok[l] & (L.step2[l] < converged2);
    if (done == kBatch && n == kBatch) {  // the usual case
      for (int l = 0; l < kBatch; ++l) q[first + l] = lane_quaternion(L, l);
      store_batch(first, r);
      continue;
    }
    for (int l = 0; l < n; ++l) {
      const int k = first + l;
      if (!ok[l]) {
        const Mat3 R = q[k].toRotationMatrix();
        double rk[9];
        for (int c = 0; c < 9; ++c) rk[c] = R(c / 3, c % 3);
        store(k, rk, 1);
      } else if (L.step2[l] < converged2) {
        q[k] = lane_quaternion(L, l);
        store(k, &r[0][l], kBatch);
      } else {  // not there yet (a large rotation since the last call, or no finite step)
        if (L.step2[l] <= std::numeric_limits<double>::max()) q[k] = lane_quaternion(L, l);
        fallback(k);
      }
    }
  }
}

}  // namespace

namespace {

// The batched iterations on count 3x3 matrices to the given accuracy.
COROTATE_CLONE_INLINE void extract_matrices(const Mat3* F, Eigen::Quaterniond* q, Mat3* R, int count,
                                            Accuracy accuracy) {
  extract_batches([F](int k, int i, int j) { return F[k](i, j); }, q,
                  [R](int k, const double* r, int stride) {
                    for (int c = 0; c < 9; ++c) R[k](c / 3, c % 3) = r[c * stride];
                  },
                  [R](int first, const double (&r)[9][kBatch]) {
                    for (int l = 0; l < kBatch; ++l)
                      for (int c = 0; c < 9; ++c) R[first + l](c / 3, c % 3) = r[c][l];
                  },
                  [&](int k) { R[k] = extract_rotation(F[k], q[k]); }, count, accuracy);
}

}  // namespace

COROTATE_CPU_CLONES void extract_rotations(const Mat3* F, Eigen::Quaterniond* q, Mat3* R, int count) {
  extract_matrices(F, q, R, count, kRoundOff);
}

COROTATE_CPU_CLONES void extract_rotations_roughly(const Mat3* F, Eigen::Quaterniond* q, Mat3* R, int count) {
  extract_matrices(F, q, R, count, Accuracy{1, kRoughStep});
}

COROTATE_CPU_CLONES void extract_rotations(const double (&F)[3][3][kRotationLanes], Eigen::Quaterniond* q,
                                           double (&R)[3][3][kRotationLanes], int count) {
  extract_batches([&F](int k, int i, int j) { return F[i][j][k]; }, q,
                  [&R](int k, const double* r, int stride) {
                    for (int c = 0; c < 9; ++c) R[c / 3][c % 3][k] = r[c * stride];
                  },
                  [&R](int, const double (&r)[9][kBatch]) {  // (the same layout: plain copies)
                    for (int c = 0; c < 9; ++c)
                      for (int l = 0; l < kBatch; ++l) R[c / 3][c % 3][l] = r[c][l];
                  },
                  [&](int k) {
                    Mat3 Fk, Rk;
                    for (int i = 0; i < 3; ++i)
                      for (int j = 0; j < 3; ++j) Fk(i, j) = F[i][j][k];
                    Rk = extract_rotation(Fk, q[k]);
                    for (int i = 0; i < 3; ++i)
                      for (int j = 0; j < 3; ++j) R[i][j][k] = Rk(i, j);
                  },
                  count);
}

}  // namespace corotate
