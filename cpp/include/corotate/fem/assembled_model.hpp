// One assembled force model for every element kernel (see element_kernel.hpp): it owns the
// rest shape, the connectivity, the sparsity pattern with each element's block indices, the
// element masses and the element loop, and gathers, scatters and assembles what the kernel
// computes per element. Linear, co-rotational, hyperelastic and membrane models are all
// AssembledModel<SomeKernel>.
//
// The pattern is built once from the connectivity and each element keeps the indices of its
// 3x3 blocks in the value array, so assembly is a scatter-add with no search and no
// allocation. Element stiffness matrices are symmetric: kernels fill the upper blocks, which
// are added and mirrored, and the diagonal blocks are symmetrised, so the assembled matrix is
// exactly symmetric. The one exception is the Tangent of a kernel that declares
// symmetric_tangent = false (co-rotated hexes): its N x N blocks are added as they are.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <sstream>
#include <type_traits>
#include <vector>

#include "corotate/fem/batch_scatter.hpp"
#include "corotate/fem/element_kernel.hpp"
#include "corotate/fem/sweep_schedule.hpp"
#include "corotate/fem/validate_mesh.hpp"
#include "corotate/materials/psd_projection.hpp"
#include "corotate/models/force_model.hpp"
#include "corotate/parallel.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate {

template <class Kernel>
class AssembledModel final : public ForceModel {
 public:
  using ElementType = typename Kernel::ElementType;
  static constexpr int N = ElementType::num_nodes;
  using NodeMatrix = typename KernelTypes<ElementType>::NodeMatrix;
  using Stiffness = typename KernelTypes<ElementType>::Stiffness;
  using NodeScalars = typename KernelTypes<ElementType>::NodeScalars;

  // rest: 3 x n node positions; cells: m x N node indices (VTK ordering); materials: one
  // Material, or one per region with each cell's region. Throws InvalidInput naming the bad
  // node, cell, element, region or parameter.
  AssembledModel(const Nodes& rest, const Connectivity& cells, const RegionMaterials& materials,
                 const ModelOptions& options = ModelOptions());

  const char* name() const override { return Kernel::name; }
  std::unique_ptr<ForceModel> clone() const override { return std::make_unique<AssembledModel>(*this); }
  Index num_nodes() const override { return rest_.cols(); }
  Index num_elements() const { return cells_.rows(); }
  const Nodes& rest_positions() const override { return rest_; }
  const Connectivity& cells() const { return cells_; }
  const BlockSparseMatrix& pattern() const override { return pattern_; }
  BlockSparseMatrix mass_matrix(bool lumped) const override;
  bool is_linear() const override { return Kernel::constant_stiffness; }
  bool symmetric_tangent() const override { return kernel_symmetric_tangent<Kernel>; }
  // The batched sweep (co-rotated tets) scatters into float32 as well.
  bool assembles_single_precision() const override {
    return kernel_sweeps_batches<Kernel> && !project_psd_ && Kernel::forces_linear_given_frame;
  }
  // The co-rotated tets' frames are their rotations (kept as quaternions); a constant
  // stiffness has no frames to turn.
  bool measures_frame_drift() const override { return Kernel::constant_stiffness || assembles_single_precision(); }
  bool stiffness_turns() const override { return !Kernel::constant_stiffness; }
  void evaluate(const Nodes& x, const Request& what, Results& out) override;
  // The restore point costs no copy of the caches (half a MB at 15,360 tets, ~2 % of a
  // step): saving swaps the buffers, so the current caches become the restore point, and the
  // next sweep reads each element's cache from there and writes it to the other buffer,
  // batch by batch while both are in cache (copy_saved_caches). Restoring only marks the
  // restore point current again; it stays intact for the next restore.
  void save_caches() override {
    if constexpr (has_caches) {
      if (caches_stale_) return;  // saved_caches_ already holds the current caches
      saved_caches_.resize(caches_.size());
      std::swap(caches_, saved_caches_);
      caches_stale_ = true;
    }
  }
  void restore_caches() override {
    if constexpr (has_caches)
      if (saved_caches_.size() == caches_.size()) caches_stale_ = true;
  }
  void reset_caches() override {
    if constexpr (has_caches) {
      caches_.assign(caches_.size(), typename Kernel::Cache{});
      caches_stale_ = false;
    }
  }

 private:
  static const RegionMaterials& validated(const RegionMaterials& m, Index num_cells) {
    m.validate(num_cells);
    return m;
  }
  void gather(const Nodes& x, Index e, NodeMatrix& xe) const {
    for (int a = 0; a < N; ++a) xe.col(a) = x.col(cells_(e, a));
  }
  void scatter(Index e, const NodeMatrix& fe, Nodes& f) const {
    for (int a = 0; a < N; ++a) f.col(cells_(e, a)) += fe.col(a);
  }
  // The stiffness sink of the global matrix: block (a, b), a <= b, of element e goes to its
  // global block and, mirrored, to (b, a); diagonal blocks are symmetrised.
  struct GlobalSink {
    BlockSparseMatrix& A;
    const int* ids;
    double scale;
    void add(int a, int b, const Mat3& block) {
      if (a == b) {
        A.block(ids[a * N + a]) += (0.5 * scale) * (block + block.transpose());
      } else {
        const Mat3 scaled = scale * block;
        A.block(ids[a * N + b]) += scaled;
        A.block(ids[b * N + a]) += scaled.transpose();
      }
    }
  };
  void scatter(Index e, double scale, const Stiffness& Ke, BlockSparseMatrix& A) const;
  using Batch = ForceStiffnessBatch<N, kernel_frame_batch<Kernel>>;
  // The forces of element e = lane b of a batched kernel's output (its stiffness blocks go
  // to the matrix batch by batch: add_batch_blocks).
  void scatter(Index e, const Batch& batch, int b, Nodes& f) const {
    for (int a = 0; a < N; ++a)
      for (int i = 0; i < 3; ++i) f(i, cells_(e, a)) += batch.f[a][i][b];
  }
  // All N x N blocks of Ke as they are (a non-symmetric tangent).
  void scatter_all_blocks(Index e, double scale, const Stiffness& Ke, BlockSparseMatrix& A) const {
    const int* ids = block_ids_.data() + e * N * N;
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) A.block(ids[a * N + b]) += scale * Ke.template block<3, 3>(3 * a, 3 * b);
  }
  void model_stiffness(const typename Kernel::Element& el, const typename Kernel::Frame& frame, const NodeMatrix& xe,
                       Stiffness& Ke) const {
    ElementMatrixSink<N> sink{Ke};
    kernel_.stiffness(el, frame, xe, sink);
    if (project_psd_) {
      mirror_upper_blocks(Ke);
      project_psd<3 * N>(Ke);
    }
  }
  // Lower blocks (a > b) from the upper ones, for what reads the whole matrix.
  static void mirror_upper_blocks(Stiffness& Ke) {
    for (int a = 1; a < N; ++a)
      for (int b = 0; b < a; ++b)
        Ke.template block<3, 3>(3 * a, 3 * b) = Ke.template block<3, 3>(3 * b, 3 * a).transpose();
  }
  void evaluate_constant(const Nodes& x, const Request& what, Results& out);
  void schedule_chunks();

  Kernel kernel_;
  Nodes rest_;
  Connectivity cells_;
  bool project_psd_;
  BlockSparseMatrix pattern_;
  std::vector<int> block_ids_;  // N * N per element: global block of element block (a, b)
  std::vector<ProductBlockTargets<N>> product_targets_;  // per element, for batched kernels
  // The same in the stored blocks of a float32 system (Results::single_stiffness), made
  // for the layout single_layout_ when one is first given.
  std::vector<ProductBlockTargets<N>> single_targets_;
  std::uint64_t single_layout_ = 0;
  void target_single_precision(const SinglePrecisionSymmetric& single);
  // Per batch of kFrameBatch elements (batches start at multiples of kFrameBatch: kChunk is
  // one), the kernel's packed constants, for batched kernels.
  std::vector<typename KernelBatchElements<Kernel>::type> batch_elements_;
  std::vector<typename Kernel::Element> elements_;  // empty for constant-stiffness kernels
  static constexpr bool has_caches = !std::is_empty_v<typename Kernel::Cache>;
  std::vector<typename Kernel::Cache> caches_, saved_caches_;
  // caches_ is out of date: the current caches are in saved_caches_ (see save_caches). Every
  // sweep visits every element and copies its range first; only a sweep that finished
  // clears the flag (after a failed one, the restore point is still intact).
  bool caches_stale_ = false;
  void copy_saved_caches(Index first, Index count) {
    if constexpr (has_caches)
      if (caches_stale_) std::copy_n(saved_caches_.begin() + first, count, caches_.begin() + first);
  }
  std::vector<ElementMass<N>> masses_;
  // The element sweep runs over chunks of kChunk consecutive elements in the order of a
  // nested dissection of the chunks (sweep_schedule.hpp): the parts of a phase share no node,
  // so they scatter into disjoint entries and run concurrently (no atomics, no per-thread
  // copies of the matrix). The order depends on the mesh alone and chunks' energies are summed
  // in chunk order: the result does not depend on the thread count.
  // 512: the natural element order's cache reuse survives within a chunk (chunks of 64 made
  // the one-thread assembly at 15,360 tets ~40 % slower).
  static constexpr Index kChunk = 512;
  static constexpr int kFrameBatch = kernel_frame_batch<Kernel>;
  SweepSchedule schedule_;
  std::vector<double> chunk_energy_;
  // The element rotations of the last sweep that assembled with Request::frame_drift (valid
  // only after that sweep finished), and per chunk the smallest |q . q_assembled| of a
  // drift-measuring sweep: cos of half the largest angle an element turned since.
  std::vector<Eigen::Quaterniond> assembled_frames_;
  bool have_assembled_frames_ = false;
  std::vector<double> chunk_alignment_;
  std::vector<Index> chunk_inverted_;
  std::vector<std::exception_ptr> chunk_error_;
  BlockSparseMatrix constant_stiffness_;  // K, assembled once, for constant-stiffness kernels
  Vec displacement_, product_;            // work vectors of the constant-stiffness path
};

template <class Kernel>
AssembledModel<Kernel>::AssembledModel(const Nodes& rest, const Connectivity& cells, const RegionMaterials& materials,
                                       const ModelOptions& options)
    : kernel_(validated(materials, cells.rows()), options),
      rest_(rest),
      cells_(cells),
      project_psd_(options.project_psd) {
  validate_mesh(rest, cells, N, ElementType::name);
  if constexpr (ElementType::dim == 2) {
    if (!std::isfinite(options.thickness) || options.thickness <= 0) {
      std::ostringstream msg;
      msg << "thickness of the " << ElementType::name << " sheet must be positive and finite, got "
          << options.thickness;
      throw InvalidInput(msg.str());
    }
  }
  pattern_ = BlockSparseMatrix::from_cells(rest.cols(), cells);
  const Index m = cells.rows();
  block_ids_.resize(m * N * N);
  elements_.reserve(m);
  masses_.reserve(m);
  NodeMatrix X;
  for (Index e = 0; e < m; ++e) {
    gather(rest, e, X);
    elements_.push_back(kernel_.precompute(X, e, materials.region_of(e)));
    masses_.push_back(element_mass<ElementType>(X, e, materials.of_cell(e).density, options.thickness));
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) block_ids_[(e * N + a) * N + b] = pattern_.block_index(cells(e, a), cells(e, b));
  }
  if constexpr (Kernel::constant_stiffness) {
    // K never changes: assemble it now; forces and energy follow from it (f = -K (x - X)).
    constant_stiffness_ = pattern_;
    constant_stiffness_.set_zero();
    Stiffness Ke;
    for (Index e = 0; e < m; ++e) {
      gather(rest, e, X);
      model_stiffness(elements_[e], typename Kernel::Frame{}, X, Ke);
      scatter(e, 1.0, Ke, constant_stiffness_);
    }
    std::vector<typename Kernel::Element>().swap(elements_);  // K_e is no longer needed
    displacement_.resize(3 * rest.cols());
    product_.resize(3 * rest.cols());
  } else {
    caches_.resize(m);
    schedule_chunks();
    if constexpr (kernel_sweeps_batches<Kernel>) {
      static_assert(kChunk % kFrameBatch == 0, "a chunk is whole batches");
      for (Index first = 0; first < m; first += kFrameBatch)
        batch_elements_.push_back(
            kernel_.pack_batch(&elements_[first], static_cast<int>(std::min<Index>(kFrameBatch, m - first))));
      product_targets_.reserve(m);
      for (Index e = 0; e < m; ++e) {
        int nodes[N];
        for (int a = 0; a < N; ++a) nodes[a] = static_cast<int>(cells(e, a));
        product_targets_.push_back(product_block_targets<N>(pattern_, block_ids_.data() + e * N * N, nodes));
      }
    }
  }
}

template <class Kernel>
void AssembledModel<Kernel>::schedule_chunks() {
  schedule_ = schedule_sweep(cells_.data(), N, num_elements(), num_nodes(), kChunk);
  chunk_energy_.assign(schedule_.num_chunks, 0.0);
  chunk_alignment_.assign(schedule_.num_chunks, 1.0);
  chunk_inverted_.assign(schedule_.num_chunks, 0);
  chunk_error_.assign(schedule_.num_chunks, nullptr);
}

template <class Kernel>
BlockSparseMatrix AssembledModel<Kernel>::mass_matrix(bool lumped) const {
  BlockSparseMatrix M = pattern_;
  M.set_zero();
  for (Index e = 0; e < num_elements(); ++e) {
    const int* ids = block_ids_.data() + e * N * N;
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) {
        if (lumped && a != b) continue;
        const double value = lumped ? masses_[e].lumped(a) : masses_[e].consistent(a, b);
        M.block(ids[a * N + b]).diagonal().array() += value;
      }
  }
  return M;
}

template <class Kernel>
void AssembledModel<Kernel>::scatter(Index e, double scale, const Stiffness& Ke, BlockSparseMatrix& A) const {
  GlobalSink sink{A, block_ids_.data() + e * N * N, scale};
  for (int a = 0; a < N; ++a)
    for (int b = a; b < N; ++b) sink.add(a, b, Ke.template block<3, 3>(3 * a, 3 * b));
}

template <class Kernel>
void AssembledModel<Kernel>::target_single_precision(const SinglePrecisionSymmetric& single) {
  if constexpr (kernel_sweeps_batches<Kernel>) {
    single_targets_ = product_targets_;
    for (auto& t : single_targets_) {
      for (int& k : t.diagonal) k = single.block_position(k);
      for (int& k : t.upper) k = single.block_position(k);
      for (int& k : t.lower)
        if (k >= 0) k = single.block_position(k);
    }
    single_layout_ = single.layout_id();
  }
}

template <class Kernel>
void AssembledModel<Kernel>::evaluate(const Nodes& x, const Request& what, Results& out) {
  check_evaluation(x, what, out);
  if constexpr (Kernel::constant_stiffness) {
    evaluate_constant(x, what, out);
  } else {
    const StiffnessKind kind = out.stiffness || out.single_stiffness ? what.stiffness : StiffnessKind::None;
    const bool linearize = what.forces && what.forces_at;
    // The Model stiffness goes straight to the global matrix unless it is needed as an
    // element matrix: for PSD projection, or to linearise the forces.
    const bool direct_scatter = !project_psd_ && (!linearize || Kernel::forces_linear_given_frame);
    if (kind == StiffnessKind::Geometric && !Kernel::has_geometric_stiffness)
      throw InvalidInput(std::string("the '") + Kernel::name +
                         "' model has no separate geometric stiffness (the hyperelastic models have one)");
    // One element: gather, frame, what was asked, scatter. Touches only the entries of its
    // own nodes (see schedule_chunks).
    auto diagnose = [&](Index e, const NodeMatrix& xe, const typename Kernel::Frame& frame, double& energy,
                        Index& inverted) {
      if (what.energy) energy += kernel_.energy(elements_[e], frame, xe);
      if (what.count_inverted && !(kernel_.volume_ratio(elements_[e], frame, xe) > 0)) ++inverted;
    };
    // The hot path of the implicit step (forces and the Model stiffness, scattered straight
    // into the global matrix) runs a batch of elements at once where the kernel can.
    bool batched = false;
    if constexpr (kernel_sweeps_batches<Kernel>)
      batched = (kind == StiffnessKind::Model || (kind == StiffnessKind::None && what.frame_drift)) && direct_scatter &&
                what.forces;
    // Frames compared with the recorded ones and, where the sweep assembles, recorded.
    const bool measure_drift = batched && what.frame_drift;
    const bool mark_frames = measure_drift && kind == StiffnessKind::Model;
    const bool had_frames = have_assembled_frames_;
    if (mark_frames) {
      have_assembled_frames_ = false;  // until this sweep has finished
      assembled_frames_.resize(num_elements());
    }
    // (check_evaluation let a float32 system through only for this path.)
    SinglePrecisionSymmetric* single = out.single_stiffness;
    if (single && !batched)
      throw InvalidInput(std::string("the '") + Kernel::name + "' model: no float32 assembly here");
    if (single && single_layout_ != single->layout_id()) target_single_precision(*single);
    const double stiffness_scale = single ? what.stiffness_scale / single->unscale() : what.stiffness_scale;
    auto element = [&](Index e, const NodeMatrix& xe, const typename Kernel::Frame& frame, NodeMatrix& ye,
                       NodeMatrix& fe, Stiffness& Ke, NodeScalars& k, double& energy, Index& inverted) {
      const auto& el = elements_[e];
      diagnose(e, xe, frame, energy, inverted);
      bool have_model_stiffness = false;
      bool scattered = false;
      bool all_blocks = false;  // Ke is a non-symmetric tangent
      if (kind == StiffnessKind::Model && direct_scatter) {
        // Straight into the global matrix: no element matrix in between (the hot path of
        // the co-rotational step).
        GlobalSink sink{*out.stiffness, block_ids_.data() + e * N * N, what.stiffness_scale};
        kernel_.stiffness(el, frame, xe, sink);
        scattered = true;
      } else if (kind == StiffnessKind::Model) {
        model_stiffness(el, frame, xe, Ke);
        have_model_stiffness = true;
      } else if (kind == StiffnessKind::Tangent) {
        if (kernel_.tangent(el, frame, xe, Ke)) all_blocks = !kernel_symmetric_tangent<Kernel>;
        else model_stiffness(el, frame, xe, Ke), have_model_stiffness = true;
      } else if (kind == StiffnessKind::Geometric) {
        if constexpr (Kernel::has_geometric_stiffness) {
          kernel_.geometric_stiffness(el, xe, k, e);
          const int* ids = block_ids_.data() + e * N * N;
          for (int a = 0; a < N; ++a)
            for (int b = 0; b < N; ++b)
              out.stiffness->block(ids[a * N + b]).diagonal().array() += what.stiffness_scale * k(a, b);
        }
      }
      if (what.forces) {
        if (!linearize) {
          kernel_.forces(el, frame, xe, fe);
        } else {
          gather(*what.forces_at, e, ye);
          if constexpr (Kernel::forces_linear_given_frame) {
            kernel_.forces(el, frame, ye, fe);
          } else {
            kernel_.forces(el, frame, xe, fe);
            if (!have_model_stiffness) model_stiffness(el, frame, xe, Ke), have_model_stiffness = true;
            mirror_upper_blocks(Ke);
            ye -= xe;
            Eigen::Map<Eigen::Matrix<double, 3 * N, 1>>(fe.data()).noalias() -=
                Ke * Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>>(ye.data());
          }
        }
        scatter(e, fe, *out.forces);
      }
      if (all_blocks) scatter_all_blocks(e, what.stiffness_scale, Ke, *out.stiffness);
      else if ((kind == StiffnessKind::Model || kind == StiffnessKind::Tangent) && !scattered)
        scatter(e, what.stiffness_scale, Ke, *out.stiffness);
    };
    // An exception must not escape a parallel loop (it would terminate the process): each
    // chunk keeps its own, and the one of the lowest chunk is rethrown after the sweep.
    const Index m = num_elements();
    std::fill(chunk_error_.begin(), chunk_error_.end(), nullptr);
    for (const auto& parts : schedule_.phases) {
      const Index count = static_cast<Index>(parts.size());
      parallel_for(count, count > 1, [&](Index i) {
        for (const Index c : parts[i]) {
          NodeMatrix xe[kFrameBatch], ye, fe;
          Batch batch;
          batch.single = single != nullptr;
          batch.stiffness = kind == StiffnessKind::Model;
          double alignment = 1;
          typename Kernel::Frame frames[kFrameBatch];
          Stiffness Ke;
          NodeScalars k;
          double energy = 0;
          Index inverted = 0;
          try {
            // The implicit step's sweep a batch at a time where the kernel batches it; otherwise
            // the frames (rotations) of kFrameBatch elements at once where the kernel batches
            // them, then the rest element by element.
            // A batch's energy, inversions, forces and blocks, from the batched kernel's output.
            auto finish_batch = [&](Index first, int count) {
              for (int b = 0; b < count; ++b) {
                if (what.energy) energy += batch.energy[b];
                if (what.count_inverted && !(batch.volume_ratio[b] > 0)) ++inverted;
                scatter(first + b, batch, b, *out.forces);
              }
              if constexpr (kernel_sweeps_batches<Kernel>) {
                if (measure_drift && had_frames)
                  for (int b = 0; b < count; ++b) {
                    const Index e = first + b;
                    const Eigen::Quaterniond recorded =
                        what.frame_turn ? what.frame_turn[what.frame_turn_of_node[cells_(e, 0)]] * assembled_frames_[e]
                                        : assembled_frames_[e];
                    alignment = std::min(alignment, std::abs(caches_[e].q.dot(recorded)));
                  }
                if (mark_frames)
                  for (int b = 0; b < count; ++b) assembled_frames_[first + b] = caches_[first + b].q;
                else if (measure_drift) return;  // no blocks
              }
              if (single) add_batch_product_blocks(batch, count, &single_targets_[first], single->values());
              else if (what.lower_blocks)
                add_batch_blocks(batch, count, block_ids_.data() + first * N * N, out.stiffness->values().data());
              else add_batch_product_blocks(batch, count, &product_targets_[first], out.stiffness->values().data());
            };
            for (Index first = c * kChunk, last = std::min(m, first + kChunk); first < last; first += kFrameBatch) {
              const int count = static_cast<int>(std::min<Index>(kFrameBatch, last - first));
              copy_saved_caches(first, count);
              if constexpr (kernel_sweeps_batches<Kernel>) {
                if (batched) {
                  kernel_.sweep_batch(batch_elements_[first / kFrameBatch], x, linearize ? *what.forces_at : x,
                                      cells_.data() + first * N, &caches_[first], count, stiffness_scale, batch);
                  finish_batch(first, count);
                  continue;
                }
              }
              for (int b = 0; b < count; ++b) gather(x, first + b, xe[b]);
              if constexpr (kFrameBatch > 1) {
                kernel_.frames(&elements_[first], xe, &caches_[first], frames, count);
              } else {
                frames[0] = kernel_.frame(elements_[first], xe[0], caches_[first]);
              }
              for (int b = 0; b < count; ++b) element(first + b, xe[b], frames[b], ye, fe, Ke, k, energy, inverted);
            }
          } catch (...) {
            chunk_error_[c] = std::current_exception();
          }
          chunk_energy_[c] = energy;
          chunk_inverted_[c] = inverted;
          chunk_alignment_[c] = alignment;
        }
      });
    }
    for (const auto& error : chunk_error_)
      if (error) std::rethrow_exception(error);
    caches_stale_ = false;
    double energy = 0;
    Index inverted = 0;
    for (size_t c = 0; c < chunk_energy_.size(); ++c) {
      energy += chunk_energy_[c];
      inverted += chunk_inverted_[c];
    }
    if (what.energy) out.energy = energy;
    if (what.count_inverted) out.inverted = inverted;
    if (mark_frames) have_assembled_frames_ = true;
    if (measure_drift) {
      double alignment = 1;
      for (const double a : chunk_alignment_) alignment = std::min(alignment, a);
      out.frame_drift = had_frames ? 2 * std::acos(std::min(1.0, alignment)) : std::numeric_limits<double>::infinity();
    }
  }
}

template <class Kernel>
void AssembledModel<Kernel>::evaluate_constant(const Nodes& x, const Request& what, Results& out) {
  if (what.stiffness == StiffnessKind::Geometric && out.stiffness)
    throw InvalidInput(std::string("the '") + Kernel::name + "' model has no separate geometric stiffness");
  if (what.frame_drift) out.frame_drift = 0;  // K never turns
  if (what.energy || what.forces) {
    // The force is linear, so its linearisation about x evaluated at y is the force at y.
    const Nodes& at = (what.forces && what.forces_at) ? *what.forces_at : x;
    displacement_ = as_dofs(at) - as_dofs(rest_);
    constant_stiffness_.multiply(displacement_, product_);
    if (what.forces) as_dofs(*out.forces) -= product_;
    if (what.energy) {
      if (&at != &x) {
        displacement_ = as_dofs(x) - as_dofs(rest_);
        constant_stiffness_.multiply(displacement_, product_);
      }
      out.energy = 0.5 * displacement_.dot(product_);
    }
  }
  if (out.stiffness && what.stiffness != StiffnessKind::None) {
    auto& dst = out.stiffness->values();
    const auto& src = constant_stiffness_.values();
    for (size_t v = 0; v < dst.size(); ++v) dst[v] += what.stiffness_scale * src[v];
  }
}

}  // namespace corotate
