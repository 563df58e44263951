// All elements of one type in a body: rest shape, connectivity, per-element precomputed
// matrices, and the block indices that map each element block into the global pattern.
#pragma once

#include <vector>

#include "corotate/elements/element_matrices.hpp"
#include "corotate/sparse/block_sparse_matrix.hpp"

namespace corotate {

// Checks what any element set needs: finite rest positions, in-range indices, sane shape.
void validate_mesh(const Nodes& rest, const Connectivity& cells, int nodes_per_cell, const char* cell_name);

template <class E>
class ElementSet {
 public:
  static constexpr int N = E::num_nodes;
  using Matrices = ElementMatrices<E>;
  using NodeMatrix = typename Matrices::NodeMatrix;
  using Stiffness = typename Matrices::Stiffness;

  // rest: 3 x n node coordinates; cells: m x N node indices (VTK ordering).
  ElementSet(const Nodes& rest, const Connectivity& cells, const Material& material)
      : rest_(rest), cells_(cells), material_(material) {
    validate_mesh(rest, cells, N, E::name);
    material.validate();
    pattern_ = BlockSparseMatrix::from_cells(rest.cols(), cells);
    elements_.reserve(cells.rows());
    stiffness_.reserve(cells.rows());
    block_ids_.resize(cells.rows() * N * N);
    for (Index e = 0; e < cells.rows(); ++e) {
      Matrices m = compute_element_matrices<E>(gather(rest, e), material, e);
      stiffness_.push_back(m.stiffness);
      elements_.push_back({m.mass, m.lumped_mass, m.centre_gradient, m.volume});
      for (int a = 0; a < N; ++a)
        for (int b = 0; b < N; ++b)
          block_ids_[(e * N + a) * N + b] = pattern_.block_index(cells(e, a), cells(e, b));
    }
  }

  Index num_elements() const { return cells_.rows(); }
  Index num_nodes() const { return rest_.cols(); }
  const Nodes& rest() const { return rest_; }
  const Connectivity& cells() const { return cells_; }
  const Material& material() const { return material_; }
  const auto& element(Index e) const { return elements_[e]; }
  // K_e of element e; only until release_stiffness().
  const Stiffness& stiffness(Index e) const { return stiffness_[e]; }
  // Models that do not need K_e during the simulation (the linear model, once it has
  // assembled K; co-rotated tets) free it: 1.1 kB per tet, 28.8 kB per Hex20.
  void release_stiffness() { std::vector<Stiffness>().swap(stiffness_); }
  const BlockSparseMatrix& pattern() const { return pattern_; }
  // Global block index of element e's block (a, b).
  const int* block_ids(Index e) const { return block_ids_.data() + e * N * N; }

  NodeMatrix gather(const Nodes& x, Index e) const {
    NodeMatrix xe;
    for (int a = 0; a < N; ++a) xe.col(a) = x.col(cells_(e, a));
    return xe;
  }

  // Global mass matrix in the stiffness pattern: consistent (m_ab I_3 blocks) or lumped.
  BlockSparseMatrix mass_matrix(bool lumped) const {
    BlockSparseMatrix M = pattern_;
    M.set_zero();
    for (Index e = 0; e < num_elements(); ++e) {
      const int* ids = block_ids(e);
      for (int a = 0; a < N; ++a)
        for (int b = 0; b < N; ++b) {
          if (lumped && a != b) continue;
          const double m = lumped ? elements_[e].lumped_mass(a) : elements_[e].mass(a, b);
          M.block(ids[a * N + b]).diagonal().array() += m;
        }
    }
    return M;
  }

 private:
  Nodes rest_;
  Connectivity cells_;
  Material material_;
  struct Element {  // what every model keeps per element
    Eigen::Matrix<double, N, N> mass;
    Eigen::Matrix<double, N, 1> lumped_mass;
    typename Matrices::Gradient centre_gradient;
    double volume;
  };
  std::vector<Element> elements_;
  std::vector<Stiffness> stiffness_;
  BlockSparseMatrix pattern_;
  std::vector<int> block_ids_;
};

}  // namespace corotate
