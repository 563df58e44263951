#include "corotate/models/mass_spring.hpp"

#include <cmath>
#include <sstream>

namespace corotate {

namespace {

std::string spring_label(size_t s, const Spring& sp) {
  std::ostringstream o;
  o << "spring " << s << " (nodes " << sp.i << ", " << sp.j << ")";
  return o.str();
}

}  // namespace

MassSpring::MassSpring(const Nodes& rest, std::vector<Spring> springs, const Vec& masses)
    : rest_(rest), springs_(std::move(springs)), masses_(masses) {
  const Index n = rest_.cols();
  if (n == 0) throw InvalidInput("a mass-spring system needs at least one node");
  if (masses_.size() != n) {
    std::ostringstream msg;
    msg << "masses has " << masses_.size() << " entries for " << n << " nodes";
    throw InvalidInput(msg.str());
  }
  if (Index i = first_non_finite_node(rest_); i >= 0)
    throw InvalidInput("position of node " + std::to_string(i) + " is not finite");
  for (Index i = 0; i < n; ++i)
    if (!(masses_[i] > 0) || !std::isfinite(masses_[i])) {
      std::ostringstream msg;
      msg << "mass of node " << i << " is " << masses_[i] << "; masses must be positive and finite";
      throw InvalidInput(msg.str());
    }
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(springs_.size());
  for (size_t s = 0; s < springs_.size(); ++s) {
    const Spring& sp = springs_[s];
    for (int node : {sp.i, sp.j})
      if (node < 0 || node >= n) {
        std::ostringstream msg;
        msg << "spring " << s << " refers to node " << node << ", out of range [0, " << n << ")";
        throw InvalidInput(msg.str());
      }
    if (sp.i == sp.j)
      throw InvalidInput("spring " + std::to_string(s) + " joins node " + std::to_string(sp.i) + " to itself");
    auto check = [&](double value, const char* what) {
      if (!(value >= 0) || !std::isfinite(value)) {
        std::ostringstream msg;
        msg << spring_label(s, sp) << " has " << what << " " << value << "; it must be >= 0 and finite";
        throw InvalidInput(msg.str());
      }
    };
    check(sp.stiffness, "stiffness k =");
    check(sp.damping, "damping d =");
    check(sp.rest_length, "rest length l0 =");
    // Coincident nodes give the spring no direction: forces and damping are undefined.
    if ((rest_.col(sp.j) - rest_.col(sp.i)).norm() == 0.0)
      throw InvalidInput(spring_label(s, sp) + " joins coincident nodes: zero length, its direction is undefined");
    pairs.emplace_back(sp.i, sp.j);
  }
  pattern_ = BlockSparseMatrix::from_pairs(n, pairs);
  blocks_.reserve(springs_.size());
  for (const Spring& sp : springs_)
    blocks_.push_back({pattern_.diagonal_block(sp.i), pattern_.diagonal_block(sp.j), pattern_.block_index(sp.i, sp.j),
                       pattern_.block_index(sp.j, sp.i)});
}

BlockSparseMatrix MassSpring::mass_matrix(bool /*lumped*/) const {
  BlockSparseMatrix M = pattern_;
  M.set_zero();
  for (Index i = 0; i < num_nodes(); ++i) M.block(M.diagonal_block(i)) = masses_[i] * Mat3::Identity();
  return M;
}

void MassSpring::add_damping_forces(const Nodes& x, const Nodes& v, Nodes& f) const {
  for (const Spring& sp : springs_) {
    const Vec3 e = x.col(sp.j) - x.col(sp.i);
    // d (e . dv) e / |e|^2: eq. (2) without a square root.
    const Vec3 F = (sp.damping * e.dot(v.col(sp.j) - v.col(sp.i)) / e.squaredNorm()) * e;
    f.col(sp.i) += F;
    f.col(sp.j) -= F;
  }
}

void MassSpring::add_forces_and_damping(const Nodes& x, const Nodes& v, Nodes& f) const {
  // The per-step kernel of explicit integration: one square root, one division per spring.
  const double* xp = x.data();
  const double* vp = v.data();
  double* fp = f.data();
  for (const Spring& sp : springs_) {
    const double* xi = xp + 3 * sp.i;
    const double* xj = xp + 3 * sp.j;
    const double* vi = vp + 3 * sp.i;
    const double* vj = vp + 3 * sp.j;
    const double e0 = xj[0] - xi[0], e1 = xj[1] - xi[1], e2 = xj[2] - xi[2];
    const double l2 = e0 * e0 + e1 * e1 + e2 * e2;
    const double l = std::sqrt(l2);
    const double inv_l = 1.0 / l;
    const double rate = e0 * (vj[0] - vi[0]) + e1 * (vj[1] - vi[1]) + e2 * (vj[2] - vi[2]);  // l dl/dt
    const double s = sp.stiffness * (1.0 - sp.rest_length * inv_l) + sp.damping * rate * inv_l * inv_l;
    const double F0 = s * e0, F1 = s * e1, F2 = s * e2;
    double* fi = fp + 3 * sp.i;
    double* fj = fp + 3 * sp.j;
    fi[0] += F0, fi[1] += F1, fi[2] += F2;
    fj[0] -= F0, fj[1] -= F1, fj[2] -= F2;
  }
}

template <class BlockOf>
void MassSpring::scatter(double scale, BlockSparseMatrix& A, BlockOf block_of) const {
  for (size_t s = 0; s < springs_.size(); ++s) {
    const Mat3 H = scale * block_of(springs_[s]);
    const auto& b = blocks_[s];
    A.block(b[0]) += H;
    A.block(b[1]) += H;
    A.block(b[2]) -= H;
    A.block(b[3]) -= H;
  }
}

namespace {
// The spring Hessian k [u u^T + (1 - l0 / l) (I - u u^T)] for the spring vector e.
Mat3 spring_hessian(const Spring& sp, const Vec3& e) {
  const double l = e.norm();
  const Vec3 u = e / l;
  const Mat3 uu = u * u.transpose();
  return sp.stiffness * (uu + (1.0 - sp.rest_length / l) * (Mat3::Identity() - uu));
}
}  // namespace

void MassSpring::evaluate(const Nodes& x, const Request& what, Results& out) {
  check_evaluation(x, what, out);
  if (what.stiffness == StiffnessKind::Geometric)
    throw InvalidInput("the 'mass_spring' model has no separate geometric stiffness");
  const bool stiffness = what.stiffness != StiffnessKind::None;
  double energy = 0;
  for (size_t s = 0; s < springs_.size(); ++s) {
    const Spring& sp = springs_[s];
    const Vec3 e = x.col(sp.j) - x.col(sp.i);
    const double l = e.norm();
    if (what.energy) energy += 0.5 * sp.stiffness * (l - sp.rest_length) * (l - sp.rest_length);
    if (!what.forces && !stiffness) continue;
    Mat3 H;
    if (stiffness || what.forces_at) H = spring_hessian(sp, e);
    if (what.forces) {
      // Elastic force on node i (eq. 1), or its linearisation f(x) - K (y - x) at y.
      Vec3 F = (sp.stiffness * (l - sp.rest_length) / l) * e;
      if (what.forces_at) F += H * ((what.forces_at->col(sp.j) - what.forces_at->col(sp.i)) - e);
      out.forces->col(sp.i) += F;
      out.forces->col(sp.j) -= F;
    }
    if (stiffness) {
      const Mat3 sH = what.stiffness_scale * H;
      const auto& b = blocks_[s];
      out.stiffness->block(b[0]) += sH;
      out.stiffness->block(b[1]) += sH;
      out.stiffness->block(b[2]) -= sH;
      out.stiffness->block(b[3]) -= sH;
    }
  }
  if (what.energy) out.energy = energy;
}

void MassSpring::add_damping_matrix(const Nodes& x, double scale, BlockSparseMatrix& A) const {
  scatter(scale, A, [&](const Spring& sp) -> Mat3 {
    const Vec3 e = x.col(sp.j) - x.col(sp.i);
    return sp.damping * e * e.transpose() / e.squaredNorm();
  });
}

void MassSpring::add_stiffness_bound(double scale, BlockSparseMatrix& A) const {
  scatter(scale, A, [](const Spring& sp) -> Mat3 { return sp.stiffness * Mat3::Identity(); });
}

void MassSpring::add_damping_bound(double scale, BlockSparseMatrix& A) const {
  scatter(scale, A, [](const Spring& sp) -> Mat3 { return sp.damping * Mat3::Identity(); });
}

bool MassSpring::has_damping() const {
  for (const Spring& sp : springs_)
    if (sp.damping > 0) return true;
  return false;
}

}  // namespace corotate
