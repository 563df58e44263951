// The batched co-rotational tet kernel (corotational_tet_batch.hpp) against the one-element
// kernel: forces and stiffness blocks of random elements, full and partial batches; and the
// assembled model's batched sweep against its element-by-element requests.
#include <algorithm>
#include <random>

#include "corotate/fem/assembled_model.hpp"
#include "corotate/models/corotational_kernel.hpp"
#include "corotate/models/model_factory.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;
using fixtures::uniform;

namespace {

using Kernel = CorotationalKernel<Tet4>;
const Material kMaterial{1e6, 0.3, 1000.0};

Kernel::NodeMatrix random_tet() {  // a positively oriented, reasonably shaped tet
  for (;;) {
    const Kernel::NodeMatrix X = fixtures::random_matrix<Kernel::NodeMatrix>();
    Mat3 D;
    for (int s = 0; s < 3; ++s) D.col(s) = X.col(s + 1) - X.col(0);
    if (D.determinant() > 0.05) return X;
  }
}

}  // namespace

TEST(batched_tet_kernel_equals_the_one_element_kernel) {
  // Two materials, alternating lane by lane: each lane has its own Lame parameters.
  const Kernel kernel(RegionMaterials({kMaterial, Material{3e6, 0.45, 500.0}}, {}), ModelOptions());
  const double scale = 0.37;
  for (const int count : {1, 7, 15, kTetBatch}) {
    Kernel::Element el[kTetBatch];
    Kernel::Frame fr[kTetBatch];
    Kernel::NodeMatrix x[kTetBatch], y[kTetBatch];
    for (int b = 0; b < count; ++b) {
      el[b] = kernel.precompute(random_tet(), b, b % 2);
      // Any rotation: the formulas do not need it to be the polar one of the positions.
      fr[b].R = fixtures::random_rotation();
      x[b] = fr[b].R * random_tet();
      fr[b].F = x[b] * el[b].G;
      y[b] = x[b] + 0.1 * fixtures::random_matrix<Kernel::NodeMatrix>();
    }
    // The batch as the sweep packs it (lanes past count repeat the first element).
    const TetBatchElements packed = kernel.pack_batch(el, count);
    TetBatchInput in;
    in.elements = &packed;
    for (int lane = 0; lane < kTetBatch; ++lane) {
      const int b = lane < count ? lane : 0;
      for (int n = 0; n < 4; ++n)
        for (int i = 0; i < 3; ++i) in.y[n][i][lane] = y[b](i, n);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          in.R[i][j][lane] = fr[b].R(i, j);
          in.F[i][j][lane] = fr[b].F(i, j);
        }
    }
    ForceStiffnessBatch<4, kTetBatch> batch;
    corotational_tet_batch(in, scale, batch);
    for (int b = 0; b < count; ++b) {
      const double energy = kernel.energy(el[b], fr[b], x[b]);
      CHECK(energy > 0);
      CHECK_NEAR(batch.energy[b], energy, 1e-13 * energy);
      const double volume_ratio = kernel.volume_ratio(el[b], fr[b], x[b]);
      CHECK_NEAR(batch.volume_ratio[b], volume_ratio, 1e-13 * std::abs(volume_ratio));
      Kernel::NodeMatrix f;
      kernel.forces(el[b], fr[b], y[b], f);
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i) CHECK_NEAR(batch.f[a][i][b], f(i, a), 1e-12 * f.norm());
      Kernel::Stiffness K;
      ElementMatrixSink<4> sink{K};
      kernel.stiffness(el[b], fr[b], y[b], sink);
      int p = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = i; j < 4; ++j, ++p)
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
              CHECK_NEAR(batch.K[p][3 * r + c][b], scale * K(3 * i + r, 3 * j + c), 1e-12 * scale * K.norm());
              if (i == j) CHECK(batch.K[p][3 * r + c][b] == batch.K[p][3 * c + r][b]);  // exactly symmetric
            }
    }
  }
}

TEST(batched_sweep_equals_separate_force_and_stiffness_requests) {
  // 36 tets: batches of 16, 16 and 4.
  const auto mesh = fixtures::tet_beam(3, 2, 1);
  auto model = make_model("corotational", "tetra", mesh.points, mesh.cells, kMaterial);
  const Mat3 R = Eigen::AngleAxisd(0.8, Vec3(1, -2, 3).normalized()).toRotationMatrix();
  Nodes x = mesh.points, y = mesh.points;
  for (Index i = 0; i < x.cols(); ++i) {
    x.col(i) = R * (mesh.points.col(i) + 0.05 * Vec3(uniform(), uniform(), uniform()));
    y.col(i) = x.col(i) + 0.01 * Vec3(uniform(), uniform(), uniform());
  }
  const double scale = 1e-4;
  // The implicit step's request: forces at y linearised about x, the Model stiffness, the
  // energy and the inversion count, in one (batched) sweep.
  Request what;
  what.forces = true;
  what.forces_at = &y;
  what.energy = true;
  what.count_inverted = true;
  what.stiffness = StiffnessKind::Model;
  what.stiffness_scale = scale;
  Nodes f = Nodes::Zero(3, x.cols());
  BlockSparseMatrix K = model->pattern();
  K.set_zero();
  Results out;
  out.forces = &f;
  out.stiffness = &K;
  model->evaluate(x, what, out);
  // The same by the element-by-element paths: forces alone, stiffness alone.
  Request forces_only;
  forces_only.forces = true;
  forces_only.forces_at = &y;
  forces_only.energy = true;
  Nodes f_ref = Nodes::Zero(3, x.cols());
  Results forces_out;
  forces_out.forces = &f_ref;
  model->evaluate(x, forces_only, forces_out);
  BlockSparseMatrix K_ref = model->pattern();
  K_ref.set_zero();
  model->add_stiffness(x, StiffnessKind::Model, scale, K_ref);

  CHECK((f - f_ref).norm() <= 1e-13 * f_ref.norm());
  double norm = 0, difference = 0;
  for (size_t v = 0; v < K.values().size(); ++v) {
    norm = std::max(norm, std::abs(K_ref.values()[v]));
    difference = std::max(difference, std::abs(K.values()[v] - K_ref.values()[v]));
  }
  CHECK(norm > 0);
  CHECK(difference <= 1e-13 * norm);
  // (The rotations are warm-started from the previous call's: equal up to round-off.)
  CHECK_NEAR(out.energy, forces_out.energy, 1e-13 * forces_out.energy);
  CHECK(out.inverted == 0);
  // Exactly symmetric, as the element-by-element assembly.
  const auto& rows = K.row_start();
  for (Index i = 0; i + 1 < static_cast<Index>(rows.size()); ++i)
    for (int k = rows[i]; k < rows[i + 1]; ++k) {
      const int j = K.columns()[k];
      CHECK(Mat3(K.block(k)) == Mat3(K.block(K.block_index(j, i)).transpose()));
    }
}

TEST(a_sweep_without_stiffness_measures_how_far_the_frames_turned) {
  // 36 tets: batches of 16, 16 and 4. A sweep that assembles records the frames; later
  // sweeps without stiffness give the same forces as the full sweep and the largest angle an
  // element turned since: for a rigid turn by theta, theta itself.
  const auto mesh = fixtures::tet_beam(3, 2, 1);
  auto model = make_model("corotational", "tetra", mesh.points, mesh.cells, kMaterial);
  CHECK(model->measures_frame_drift());
  Nodes x = mesh.points;
  for (Index i = 0; i < x.cols(); ++i) x.col(i) += 0.03 * Vec3(uniform(), uniform(), uniform());
  auto sweep = [&](const Nodes& at, bool assemble, Nodes& f) {
    Request what;
    what.forces = true;
    what.forces_at = &at;
    what.energy = true;
    what.frame_drift = true;
    what.stiffness = assemble ? StiffnessKind::Model : StiffnessKind::None;
    BlockSparseMatrix K = model->pattern();
    K.set_zero();
    f.setZero(3, at.cols());
    Results out;
    out.forces = &f;
    if (assemble) out.stiffness = &K;
    model->evaluate(at, what, out);
    return out;
  };
  Nodes f, f_ref;
  CHECK(std::isinf(sweep(x, false, f).frame_drift));  // no frames recorded yet
  sweep(x, true, f);
  CHECK(sweep(x, false, f).frame_drift <= 1e-7);  // (the angle of a quaternion dot of 1 - 1e-16)
  for (const double theta : {0.01, 0.05, 0.3}) {
    const Mat3 R = Eigen::AngleAxisd(theta, Vec3(1, -2, 3).normalized()).toRotationMatrix();
    const Nodes turned = R * x;
    const Results kept = sweep(turned, false, f);
    CHECK_NEAR(kept.frame_drift, theta, 1e-7);
    // The forces of the full sweep (which then records these frames), to round-off.
    const Results full = sweep(turned, true, f_ref);
    CHECK((f - f_ref).norm() <= 1e-13 * f_ref.norm());
    CHECK_NEAR(kept.energy, full.energy, 1e-13 * full.energy);
    CHECK(sweep(turned, false, f).frame_drift <= 1e-7);
    sweep(x, true, f);  // back: the next turn is measured from x
  }
  // One element turned alone: the largest angle is its own.
  Nodes one = x;
  const Mat3 R = Eigen::AngleAxisd(0.2, Vec3(0, 0, 1)).toRotationMatrix();
  const Connectivity& cells = dynamic_cast<const AssembledModel<Kernel>&>(*model).cells();
  const Vec3 centre = 0.25 * (x.col(cells(0, 0)) + x.col(cells(0, 1)) + x.col(cells(0, 2)) + x.col(cells(0, 3)));
  for (int a = 0; a < 4; ++a) one.col(cells(0, a)) = centre + R * (x.col(cells(0, a)) - centre);
  const double drift = sweep(one, false, f).frame_drift;
  CHECK(drift >= 0.2 - 1e-7 && drift < 0.3);  // (its neighbours are sheared, less turned)
}

TEST(product_block_sweep_assembles_exactly_what_the_symmetric_product_reads) {
  // 1,519 nodes (two row chunks), numbered at random: pairs whose local order is the
  // reverse of their global one, and pairs across the chunks, in every batch.
  const auto beam = fixtures::tet_beam(30, 6, 6);
  std::vector<int> relabel(beam.points.cols());
  for (size_t i = 0; i < relabel.size(); ++i) relabel[i] = static_cast<int>(i);
  std::mt19937 rng(7);
  std::shuffle(relabel.begin(), relabel.end(), rng);
  Nodes points(3, beam.points.cols());
  for (Index i = 0; i < beam.points.cols(); ++i) points.col(relabel[i]) = beam.points.col(i);
  Connectivity cells = beam.cells;
  for (Index e = 0; e < cells.rows(); ++e)
    for (int a = 0; a < 4; ++a) cells(e, a) = relabel[cells(e, a)];
  auto model = make_model("corotational", "tetra", points, cells, kMaterial);
  CHECK(model->pattern().num_chunks() == 2);
  Nodes x = points;
  for (Index i = 0; i < x.cols(); ++i) x.col(i) += 0.02 * Vec3(uniform(), uniform(), uniform());
  Request what;
  what.forces = true;
  what.forces_at = &x;
  what.stiffness = StiffnessKind::Model;
  what.stiffness_scale = 1e-4;
  auto assemble = [&](bool lower_blocks, BlockSparseMatrix& K) {
    Nodes f = Nodes::Zero(3, x.cols());
    Results out;
    out.forces = &f;
    out.stiffness = &K;
    what.lower_blocks = lower_blocks;
    model->clone()->evaluate(x, what, out);  // each from the same warm start of the rotations
    return f;
  };
  // The full matrix, and the product blocks only over a matrix whose other blocks hold
  // stale values (as the step's mass copy leaves them).
  BlockSparseMatrix full = model->pattern(), product = model->pattern(), mass = model->pattern();
  for (double& v : mass.values()) v = uniform();
  full.assign_scaled(1.0, mass);
  product.assign_scaled(1.0, mass);
  for (double& v : product.values()) v = 7.0;
  product.assign_scaled(1.0, mass, false);
  const Nodes f_full = assemble(true, full), f_product = assemble(false, product);
  CHECK(f_full == f_product);
  Index skipped = 0, transposed_pairs = 0;
  for (Index i = 0; i < full.num_nodes(); ++i)
    for (int k = full.row_start()[i]; k < full.row_start()[i + 1]; ++k) {
      if (full.is_product_block(i, k)) {
        CHECK(Mat3(product.block(k)) == Mat3(full.block(k)));  // the same sums in the same order
      } else {
        CHECK(product.block(k).isConstant(7.0));  // left as it was
        ++skipped;
      }
      transposed_pairs += full.columns()[k] < i;
    }
  // Random numbers put about half the pairs across the two chunks: a quarter of the lower
  // triangle's blocks are skipped, the other half of them kept.
  CHECK(skipped > transposed_pairs / 3);
  CHECK(skipped < 2 * transposed_pairs / 3);
  const Vec v = fixtures::random_matrix<Vec>(full.num_dofs(), 1);
  Vec y_full(full.num_dofs()), y_product(full.num_dofs());
  full.multiply_symmetric(v, y_full);
  product.multiply_symmetric(v, y_product);
  CHECK(y_full == y_product);
}
