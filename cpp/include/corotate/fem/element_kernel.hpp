// The element-kernel concept: what a force model computes per element, and nothing else.
// AssembledModel<Kernel> (assembled_model.hpp) owns the mesh, the sparsity pattern, the
// gather/scatter, the mass and the element loop; a kernel knows nothing of assembly.
//
// A kernel is a class with
//   using ElementType = Tet4 | Hex8 | Hex20 | Tri3 | ...;     (elements/; N = num_nodes)
//   static constexpr const char* name;                        model name ("corotational", ...)
//   static constexpr bool constant_stiffness;                 K is the same at every x (linear
//                                                             FEM): the assembled model builds
//                                                             K once and derives forces and
//                                                             energy from it; then only the
//                                                             constructor, precompute and
//                                                             stiffness below are needed
//   static constexpr bool forces_linear_given_frame;          forces(frame(x), y) equals the
//                                                             linearisation f(x) - K(x)(y - x)
//                                                             (co-rotational: R held fixed)
//   static constexpr bool has_geometric_stiffness;
//   static constexpr bool symmetric_tangent;                  optional, default true: false when
//                                                             tangent() is not symmetric (the
//                                                             force is not a gradient); it then
//                                                             fills all N x N blocks
//   struct Element;  struct Frame;  struct Cache;             per-element data computed once;
//                                                             per-configuration quantities
//                                                             (a rotation); per-element state
//                                                             that only speeds up the next
//                                                             frame() (a warm start)
//   Kernel(const RegionMaterials&, const ModelOptions&);      the materials (validated) of
//                                                             the body's regions; derives
//                                                             what it uses of each
//   Element precompute(const NodeMatrix& X, Index e,          from the rest shape X (3 x N)
//                      int region) const;                     and the material of the region;
//                                                             throws InvalidInput naming e.
//                                                             Material constants go into the
//                                                             Element (K_e, the law), so the
//                                                             per-step code is the same for
//                                                             one material or many
//   Frame frame(const Element&, const NodeMatrix& x, Cache&) const;
//   static constexpr int frame_batch;                         optional, default 1: > 1 when
//   void frames(const Element*, const NodeMatrix* x,          frames() computes up to this many
//               Cache*, Frame*, int count) const;             consecutive elements' frames at
//                                                             once, faster than one by one
//   using BatchElements = ...;                                optional (kernels with frame_batch
//   BatchElements pack_batch(const Element*, int count) const; > 1), all three together: the
//   void sweep_batch(const BatchElements&, const Nodes& x,     constants of count consecutive
//       const Nodes& at, const int* nodes, Cache*, int count,  elements packed once at setup;
//       double scale, ForceStiffnessBatch<N, frame_batch>&)    then for those elements at once
//       const;                                                 (nodes: their N node indices
//                                                             each), frame() at x, forces() at
//                                                             `at`, scale times stiffness(),
//                                                             energy() and volume_ratio() at
//                                                             x: the implicit step's sweep
//   double energy(const Element&, const Frame&, const NodeMatrix& x) const;
//   void forces(const Element&, const Frame&, const NodeMatrix& x, NodeMatrix& f) const;
//                                                             f = the element's nodal forces
//   template <class Sink>
//   void stiffness(const Element&, const Frame&, const NodeMatrix& x, Sink& K) const;
//                                                             the Model stiffness (3N x 3N,
//                                                             symmetric; see force_model.hpp)
//                                                             as its 3x3 blocks (a, b), a <= b:
//                                                             K.add(a, b, block). The sink adds
//                                                             them to the global matrix (mirrored)
//                                                             or to an element matrix
//   bool tangent(const Element&, const Frame&, const NodeMatrix& x, Stiffness& K) const;
//                                                             exact -df/dx (at least the blocks
//                                                             a <= b, all of them if not
//                                                             symmetric_tangent); false where it
//                                                             is undefined (the Model one is used)
//   void geometric_stiffness(const Element&, const NodeMatrix& x, NodeScalars& k, Index e) const;
//                                                             (if has_geometric_stiffness)
//                                                             k_ab of the blocks k_ab I_3
//   double volume_ratio(const Element&, const Frame&, const NodeMatrix& x) const;
//                                                             det F (the smallest over the
//                                                             points): <= 0 for an inverted or
//                                                             flat element (not needed by
//                                                             constant-stiffness kernels)
// with NodeMatrix = Eigen::Matrix<double, 3, N>, Stiffness = 3N x 3N, NodeScalars = N x N.
// Kernels are stateless apart from Cache, so one kernel object serves every element.
#pragma once

#include <type_traits>
#include <utility>

#include "corotate/elements/element_geometry.hpp"
#include "corotate/region_materials.hpp"

namespace corotate {

// Settings that only some models use.
struct ModelOptions {
  double thickness = 1.0;    // sheet thickness [m] of membrane (triangle) elements; solids ignore it
  bool project_psd = false;  // project each element stiffness onto the PSD cone (implicit solves)
};

// Element-sized types of a kernel.
template <class E>
struct KernelTypes {
  static constexpr int N = E::num_nodes;
  using NodeMatrix = Eigen::Matrix<double, 3, N>;
  using Stiffness = Eigen::Matrix<double, 3 * N, 3 * N>;
  using NodeScalars = Eigen::Matrix<double, N, N>;
};

// A stiffness sink that writes the blocks into an element matrix (upper blocks only).
template <int N>
struct ElementMatrixSink {
  Eigen::Matrix<double, 3 * N, 3 * N>& K;
  void add(int a, int b, const Mat3& block) { K.template block<3, 3>(3 * a, 3 * b) = block; }
};

// What a kernel's sweep_batch fills, lane b for element b of the batch
// (structure of arrays, so that the kernel's loops over the lanes vectorise): the nodal
// forces, the upper 3x3 blocks (a, b), a <= b, of the scaled Model stiffness in the order
// (0,0), (0,1), ..., (0,N-1), (1,1), ..., each row-major (diagonal blocks exactly
// symmetric), the energy and the volume ratio. When the caller sets single, the blocks go
// to K_single in float32 instead (for a system assembled in float32: converted in the
// kernel's vector loop rather than entry by entry in the scatter).
template <int N, int Batch>
struct ForceStiffnessBatch {
  static constexpr int num_upper_blocks = N * (N + 1) / 2;
  alignas(64) double f[N][3][Batch];                  // f[a][i][b]: force on node a
  alignas(64) double K[num_upper_blocks][9][Batch];  // K[block][3 row + column][b]
  alignas(64) float K_single[num_upper_blocks][9][Batch];
  double energy[Batch];
  double volume_ratio[Batch];
  bool single = false;
  bool stiffness = true;  // false: no blocks (a step that keeps its system matrix)
};

// Kernel::symmetric_tangent where the kernel declares it, else true.
template <class Kernel, class = void>
struct KernelSymmetricTangent : std::true_type {};
template <class Kernel>
struct KernelSymmetricTangent<Kernel, std::void_t<decltype(Kernel::symmetric_tangent)>>
    : std::bool_constant<Kernel::symmetric_tangent> {};
template <class Kernel>
inline constexpr bool kernel_symmetric_tangent = KernelSymmetricTangent<Kernel>::value;

// Kernel::frame_batch where the kernel declares it, else 1.
template <class Kernel, class = void>
struct KernelFrameBatch : std::integral_constant<int, 1> {};
template <class Kernel>
struct KernelFrameBatch<Kernel, std::void_t<decltype(Kernel::frame_batch)>>
    : std::integral_constant<int, Kernel::frame_batch> {};
template <class Kernel>
inline constexpr int kernel_frame_batch = KernelFrameBatch<Kernel>::value;

// Whether Kernel::sweep_batch exists: frames, forces and stiffness of a batch in one pass,
// from the node positions (see CorotationalKernel<Tet4>).
template <class Kernel, class = void>
struct KernelSweepsBatches : std::false_type {};
template <class Kernel>
struct KernelSweepsBatches<
    Kernel, std::void_t<decltype(std::declval<const Kernel&>().sweep_batch(
                std::declval<const Kernel&>().pack_batch(std::declval<const typename Kernel::Element*>(), 0),
                std::declval<const Nodes&>(), std::declval<const Nodes&>(), std::declval<const int*>(),
                std::declval<typename Kernel::Cache*>(), 0, 0.0,
                std::declval<ForceStiffnessBatch<Kernel::ElementType::num_nodes, kernel_frame_batch<Kernel>>&>()))>>
    : std::true_type {};
template <class Kernel>
inline constexpr bool kernel_sweeps_batches = KernelSweepsBatches<Kernel>::value;

// Kernel::BatchElements where the kernel sweeps batches, else an empty stand-in.
struct NoBatchElements {};
template <class Kernel, bool = kernel_sweeps_batches<Kernel>>
struct KernelBatchElements {
  using type = NoBatchElements;
};
template <class Kernel>
struct KernelBatchElements<Kernel, true> {
  using type = typename Kernel::BatchElements;
};

// For kernels without per-configuration quantities or caches.
struct NoFrame {};
struct NoCache {};

}  // namespace corotate
