// The element sweep's schedule (sweep_schedule.hpp): every chunk exactly once, the parts of a
// phase node-disjoint (so they may run concurrently and the order of adds into any block is
// the schedule's, whatever the thread count), and on a well-ordered mesh the chunks nearly in
// their natural order.
#include <algorithm>
#include <random>
#include <set>

#include "corotate/fem/sweep_schedule.hpp"
#include "fixtures.hpp"
#include "test_driver.hpp"

using namespace corotate;

namespace {

// Checks the two rules; returns the chunks in the order a single thread runs them.
std::vector<int> check_schedule(const SweepSchedule& s, const Connectivity& cells, Index chunk_size) {
  const Index m = cells.rows(), per = cells.cols();
  std::vector<int> order;
  for (const auto& phase : s.phases) {
    std::vector<int> owner(cells.maxCoeff() + 1, -1);  // part of this phase that touched a node
    for (size_t q = 0; q < phase.size(); ++q)
      for (const int c : phase[q]) {
        order.push_back(c);
        for (Index e = c * chunk_size; e < std::min(m, (c + 1) * chunk_size); ++e)
          for (Index a = 0; a < per; ++a) {
            int& o = owner[cells(e, a)];
            CHECK(o == -1 || o == int(q));  // no node in two parts of one phase
            o = int(q);
          }
      }
  }
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  CHECK(Index(sorted.size()) == s.num_chunks);
  for (size_t c = 0; c < sorted.size(); ++c) CHECK(sorted[c] == int(c));  // each chunk once
  return order;
}

}  // namespace

TEST(sweep_schedule_splits_a_beam_into_concurrent_halves_and_small_separators) {
  // 80 x 8 x 8 cubes = 30,720 tets = 60 chunks of 512: three levels of splits.
  const auto mesh = fixtures::tet_beam(80, 8, 8);
  const Connectivity& cells = mesh.cells;
  const SweepSchedule s = schedule_sweep(cells.data(), 4, cells.rows(), mesh.points.cols(), 512);
  const std::vector<int> order = check_schedule(s, cells, 512);
  CHECK(s.phases.size() == 4);          // the leaves, then the separators of three levels
  CHECK(s.phases.front().size() == 8);  // 2^3 leaves run concurrently
  CHECK(s.phases.back().size() == 1);   // the first split's separator, last
  // A slab of the beam (8 x 8 cubes, 384 tets) is under a chunk: each separator is one or
  // two chunks, and the leaves keep the rest in natural order.
  Index separated = 0, out_of_order = 0;
  for (size_t p = 1; p < s.phases.size(); ++p)
    for (const auto& part : s.phases[p]) separated += Index(part.size());
  for (size_t i = 1; i < order.size(); ++i) out_of_order += order[i] < order[i - 1];
  std::printf("  %lld of 60 chunks in separators, %lld steps back in the one-thread order\n", (long long)separated,
              (long long)out_of_order);
  CHECK(separated >= 7 && separated <= 14);
  CHECK(out_of_order <= 8);
}

TEST(sweep_schedule_gives_the_thread_tests_mesh_concurrent_parts) {
  // test_parallel.cpp's beam (48 x 4 x 4 cubes, 9 chunks): its one- against two-thread
  // checks mean something only if two parts of it run at the same time.
  const auto mesh = fixtures::tet_beam(48, 4, 4);
  const SweepSchedule s = schedule_sweep(mesh.cells.data(), 4, mesh.cells.rows(), mesh.points.cols(), 512);
  check_schedule(s, mesh.cells, 512);
  CHECK(s.num_chunks == 9);
  CHECK(s.phases.front().size() == 2);
}

TEST(sweep_schedule_stays_valid_on_a_shuffled_mesh_and_small_ones) {
  auto mesh = fixtures::tet_beam(40, 4, 4);  // 3,840 tets
  std::vector<Index> perm(mesh.cells.rows());
  for (size_t e = 0; e < perm.size(); ++e) perm[e] = Index(e);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(7));
  Connectivity shuffled(mesh.cells.rows(), 4);
  for (Index e = 0; e < shuffled.rows(); ++e) shuffled.row(e) = mesh.cells.row(perm[e]);
  for (const Index chunk : {Index(1), Index(7), Index(64), Index(512), Index(100000)}) {
    for (const Connectivity* cells : {&mesh.cells, &shuffled}) {
      const SweepSchedule s = schedule_sweep(cells->data(), 4, cells->rows(), mesh.points.cols(), chunk);
      check_schedule(s, *cells, chunk);
    }
  }
  // Random order: every chunk touches every region, so the halves cannot run apart; all
  // of the second half waits as the separator (still correct, only serial).
  const SweepSchedule s = schedule_sweep(shuffled.data(), 4, shuffled.rows(), mesh.points.cols(), 64);
  CHECK(s.phases.front().size() >= 1);
  const SweepSchedule none = schedule_sweep(shuffled.data(), 4, 0, mesh.points.cols(), 64);
  CHECK(none.num_chunks == 0 && none.phases.empty());
  CHECK_THROWS(schedule_sweep(shuffled.data(), 4, shuffled.rows(), mesh.points.cols(), 0), InvalidInput);
}
