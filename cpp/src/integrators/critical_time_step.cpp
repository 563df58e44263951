#include "corotate/integrators/critical_time_step.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <vector>

namespace corotate {

EigenEstimate largest_eigenvalue(const BlockSparseMatrix& A, const Vec& s, int max_iterations, double tolerance) {
  const Index n = A.num_dofs();
  EigenEstimate out;
  if (s.size() != n) throw InvalidInput("inverse square-root mass has the wrong length");
  // Start vector: all ones with a deterministic, non-smooth perturbation so that no mode is
  // missing from it (a smooth start can be orthogonal to the highest modes of a lattice).
  Vec q(n), q_prev = Vec::Zero(n), w(n), t(n);
  unsigned state = 12345u;
  for (Index d = 0; d < n; ++d) {
    state = state * 1664525u + 1013904223u;
    q[d] = s[d] > 0 ? 1.0 + (state >> 8) * (1.0 / 16777216.0) : 0.0;
  }
  const double norm = q.norm();
  if (norm == 0) return out;  // everything fixed
  q /= norm;
  std::vector<double> alpha, beta;  // beta[j] couples q_j and q_{j+1}
  const int m_max = static_cast<int>(std::min<Index>(max_iterations, n));
  for (int j = 0; j < m_max; ++j) {
    t = s.cwiseProduct(q);  // w = S A S q
    A.multiply(t, w);
    w = s.cwiseProduct(w);
    const double a = q.dot(w);
    alpha.push_back(a);
    w -= a * q;
    if (j > 0) w -= beta.back() * q_prev;
    const double b = w.norm();
    const int m = j + 1;
    out.iterations = m;
    // Ritz values of the m x m tridiagonal matrix; cheap next to the products for m <= 80.
    if (m % 5 == 0 || m == m_max || b <= 1e-14 * std::abs(a)) {
      Eigen::MatrixXd T = Eigen::MatrixXd::Zero(m, m);
      for (int i = 0; i < m; ++i) {
        T(i, i) = alpha[i];
        if (i + 1 < m) T(i, i + 1) = T(i + 1, i) = beta[i];
      }
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(T);
      out.ritz = eig.eigenvalues()[m - 1];
      out.residual = b * std::abs(eig.eigenvectors()(m - 1, m - 1));
      if (out.residual <= tolerance * std::abs(out.ritz) || b <= 1e-14 * std::abs(a)) break;
    }
    beta.push_back(b);
    q_prev.swap(q);
    q = w / b;
  }
  out.value = out.ritz + out.residual;
  return out;
}

double critical_time_step(double omega_sq, double c) {
  if (omega_sq <= 0) return c > 0 ? 2.0 / c : std::numeric_limits<double>::infinity();
  return (std::sqrt(c * c + 4.0 * omega_sq) - c) / omega_sq;
}

}  // namespace corotate
