#include "corotate/embedding/surface_embedding.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "corotate/elements/element_list.hpp"
#include "corotate/embedding/element_search_grid.hpp"
#include "corotate/embedding/local_coordinates.hpp"
#include "corotate/fem/validate_mesh.hpp"
#include "corotate/models/rotation_extraction.hpp"

namespace corotate {

namespace {

// Below this criterion a point counts as inside (round-off on shared faces and corners).
constexpr double kInside = 1e-10;

Index first_non_finite(const Eigen::Ref<const Nodes>& x) {
  for (Index j = 0; j < x.cols(); ++j)
    if (!x.col(j).allFinite()) return j;
  return -1;
}

// Distance from point p to box [lo, hi] (0 inside).
double box_distance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).norm();
}

}  // namespace

void EmbeddingSettings::validate() const {
  if (!(max_outside_distance >= 0) || !std::isfinite(max_outside_distance))
    throw InvalidInput("max_outside_distance must be a finite number >= 0 (element sizes)");
}

SurfaceEmbedding::SurfaceEmbedding(const std::string& cell_type, const Nodes& rest, const Connectivity& cells,
                                   const Nodes& vertices, const Connectivity& triangles,
                                   const EmbeddingSettings& settings) {
  settings.validate();
  std::ostringstream msg;
  if (vertices.cols() == 0) throw InvalidInput("the surface has no vertices");
  if (Index v = first_non_finite(vertices); v >= 0) {
    msg << "surface vertex " << v << " is not finite (NaN or infinity)";
    throw InvalidInput(msg.str());
  }
  if (triangles.rows() > 0 && triangles.cols() != 3) throw InvalidInput("triangles must have shape (nt, 3)");
  for (Index t = 0; t < triangles.rows(); ++t)
    for (Index a = 0; a < 3; ++a)
      if (triangles(t, a) < 0 || triangles(t, a) >= vertices.cols()) {
        msg << "triangle " << t << " refers to vertex " << triangles(t, a) << ", out of range [0, " << vertices.cols()
            << ")";
        throw InvalidInput(msg.str());
      }
  vertices_ = vertices;
  triangles_ = triangles.rows() > 0 ? Triangles(triangles.transpose()) : Triangles(3, 0);
  num_body_nodes_ = rest.cols();
  visit_solid_element(cell_type, "embedding a surface",
                      [&](auto tag) { couple<typename decltype(tag)::type>(rest, cells, settings); });
  rest_normals_.resize(3, vertices_.cols());
  vertex_normals(vertices_, rest_normals_);
}

template <class E>
void SurfaceEmbedding::couple(const Nodes& rest, const Connectivity& cells, const EmbeddingSettings& settings) {
  constexpr int k = E::num_nodes;
  validate_mesh(rest, cells, k, E::name);
  const Index m = cells.rows(), nv = vertices_.cols();

  // Per element: the inverse map, its box and dN/dX at the centre (for rotated normals).
  std::vector<ElementInverseMap<E>> maps(m);
  Nodes lower(3, m), upper(3, m);
  centre_gradients_.resize(m * k, 3);
  double largest = 0;
  for (Index e = 0; e < m; ++e) {
    ElementNodes<E> X;
    for (int a = 0; a < k; ++a) X.col(a) = rest.col(cells(e, a));
    const Mat3 J = checked_jacobian<E>(X, E::centre(), e);  // rejects degenerate and inverted elements
    centre_gradients_.middleRows(e * k, k) = E::shape_gradient(E::centre()) * J.inverse();
    maps[e] = ElementInverseMap<E>(X);
    lower.col(e) = X.rowwise().minCoeff();
    upper.col(e) = X.rowwise().maxCoeff();
    largest = std::max(largest, maps[e].size);
  }
  const ElementSearchGrid grid(lower, upper);

  nodes_per_vertex_ = k;
  element_.assign(nv, -1);
  local_.resize(3, nv);
  outside_distance_ = Vec::Zero(nv);
  nodes_.resize(nv * k);
  weights_.resize(nv * k);
  report_ = {};
  std::vector<Index> stamp(m, -1);  // last vertex that looked at an element (no double work)

  for (Index v = 0; v < nv; ++v) {
    const Vec3 p = vertices_.col(v);
    PointInElement<E> best;
    Index best_element = -1;
    const auto consider = [&](int e) {
      if (stamp[e] == v) return;
      stamp[e] = v;
      PointInElement<E> r = maps[e].locate(p);
      if (r.criterion < best.criterion) best = r, best_element = e;
    };
    const double slack = 1e-9 * largest;
    for (auto [it, end] = grid.candidates(p); it != end && !(best.criterion <= kInside); ++it)
      if (((p - lower.col(*it)).array() >= -slack).all() && ((upper.col(*it) - p).array() >= -slack).all())
        consider(*it);

    if (!(best.criterion <= kInside)) {
      // Inside no element: the nearest element box first (growing the search cube until a
      // box lies within it), then every element whose box is within one element size of
      // that distance competes by the criterion.
      double nearest = std::numeric_limits<double>::infinity();
      const double cover = grid.covering_radius(p);
      for (double radius = grid.cell_size();; radius *= 2) {
        grid.visit_near(p, radius,
                        [&](int e) { nearest = std::min(nearest, box_distance(p, lower.col(e), upper.col(e))); });
        if (nearest <= radius || radius > cover) break;
      }
      const double reach = nearest + largest;
      grid.visit_near(p, reach, [&](int e) {
        if (box_distance(p, lower.col(e), upper.col(e)) <= reach) consider(e);
      });
    }
    if (best_element < 0) {
      std::ostringstream msg;
      msg << "surface vertex " << v << " at (" << p.transpose() << ") lies outside the body where no element's "
          << "local coordinates reach it";
      throw InvalidInput(msg.str());
    }
    if (best.criterion > kInside) {
      const double distance = (p - best.clamped_point).norm() / maps[best_element].size;
      outside_distance_(v) = distance;
      ++report_.outside;
      if (distance > report_.max_outside_distance || report_.farthest_vertex < 0)
        report_.max_outside_distance = distance, report_.farthest_vertex = v;
      if (distance > settings.max_outside_distance) {
        std::ostringstream msg;
        msg << "surface vertex " << v << " at (" << p.transpose() << ") lies " << distance
            << " element sizes outside the body (max_outside_distance = " << settings.max_outside_distance
            << "): does the surface belong to this body, in the same units and placement?";
        throw InvalidInput(msg.str());
      }
    }
    element_[v] = int(best_element);
    local_.col(v) = best.xi;
    for (int a = 0; a < k; ++a) {
      nodes_[v * k + a] = cells(best_element, a);
      weights_[v * k + a] = best.weights(a);
    }
  }

  cells_ = cells;
  used_elements_ = element_;
  std::sort(used_elements_.begin(), used_elements_.end());
  used_elements_.erase(std::unique(used_elements_.begin(), used_elements_.end()), used_elements_.end());
  rotations_.assign(m, Eigen::Quaterniond::Identity());
  element_rotation_.assign(m, Mat3::Identity());
}

void SurfaceEmbedding::check_body_positions(const Eigen::Ref<const Nodes>& x) const {
  if (x.cols() != num_body_nodes_) {
    std::ostringstream msg;
    msg << "body positions must have one row per body node (" << num_body_nodes_ << "), got " << x.cols();
    throw InvalidInput(msg.str());
  }
  if (Index i = first_non_finite(x); i >= 0)
    throw InvalidInput("body position of node " + std::to_string(i) + " is not finite (NaN or infinity)");
}

void SurfaceEmbedding::check_output(const Eigen::Ref<Nodes>& out, const char* what) const {
  if (out.cols() != num_vertices())
    throw InvalidInput(std::string(what) + " must have one row per surface vertex (" + std::to_string(num_vertices()) +
                       "), got " + std::to_string(out.cols()));
}

void SurfaceEmbedding::embed(Eigen::Ref<const Nodes> x, Eigen::Ref<Nodes> out) const {
  check_body_positions(x);
  check_output(out, "surface positions");
  const int k = nodes_per_vertex_;
  const int* node = nodes_.data();
  const double* w = weights_.data();
  for (Index v = 0; v < num_vertices(); ++v, node += k, w += k) {
    Vec3 y = w[0] * x.col(node[0]);
    for (int a = 1; a < k; ++a) y.noalias() += w[a] * x.col(node[a]);
    out.col(v) = y;
  }
}

void SurfaceEmbedding::vertex_normals(Eigen::Ref<const Nodes> y, Eigen::Ref<Nodes> out) const {
  check_output(out, "normals");
  if (y.cols() != num_vertices())
    throw InvalidInput("surface positions must have one row per surface vertex (" + std::to_string(num_vertices()) +
                       "), got " + std::to_string(y.cols()));
  out.setZero();
  for (Index t = 0; t < num_triangles(); ++t) {
    const int a = triangles_(0, t), b = triangles_(1, t), c = triangles_(2, t);
    // Twice the area times the unit normal: area weighting for free.
    const Vec3 n = (y.col(b) - y.col(a)).cross(y.col(c) - y.col(a));
    out.col(a) += n;
    out.col(b) += n;
    out.col(c) += n;
  }
  for (Index v = 0; v < num_vertices(); ++v) {
    const double length = out.col(v).norm();
    if (length > 0 && std::isfinite(length)) out.col(v) /= length;
    else out.col(v).setZero();
  }
}

void SurfaceEmbedding::rotated_normals(Eigen::Ref<const Nodes> x, Eigen::Ref<Nodes> out) {
  check_body_positions(x);
  check_output(out, "normals");
  const int k = nodes_per_vertex_;
  for (const int e : used_elements_) {
    Mat3 F = Mat3::Zero();
    for (int a = 0; a < k; ++a) F.noalias() += x.col(cells_(e, a)) * centre_gradients_.row(e * k + a);
    element_rotation_[e] = extract_rotation(F, rotations_[e]);
  }
  for (Index v = 0; v < num_vertices(); ++v) out.col(v) = element_rotation_[element_[v]] * rest_normals_.col(v);
}

}  // namespace corotate
