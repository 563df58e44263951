// The thread count of corotate's parallel loops: element sweeps (sweep_schedule.hpp),
// block-sparse matrix-vector products and the block-Jacobi smoother. OpenMP when the build
// found it (corotate::have_openmp()); without it every loop runs on the calling thread.
//
// One process-wide setting, 1 by default: a step's results depend only on the data, never
// on the thread count or scheduling (each parallel loop writes disjoint entries, and sums
// are taken per fixed chunk and added in chunk order), so threaded and single-threaded runs
// agree to the last bit. Eigen's own threading is off (EIGEN_DONT_PARALLELIZE), so this is
// the only knob.
#pragma once

namespace corotate {

bool have_openmp();
// Threads the hardware offers (omp_get_num_procs; 1 without OpenMP).
int available_threads();
// Threads the parallel loops use (default 1).
int num_threads();
// n >= 1, and 1 in a build without OpenMP (InvalidInput otherwise); more than
// available_threads() is allowed (oversubscribed).
void set_num_threads(int n);

}  // namespace corotate

// COROTATE_PARALLEL_FOR(cond): the next for loop runs on num_threads() threads, statically
// scheduled, when cond holds (small loops stay serial: a fork costs microseconds).
#ifdef _OPENMP
#define COROTATE_PRAGMA(x) _Pragma(#x)
#define COROTATE_PARALLEL_FOR(cond) \
  COROTATE_PRAGMA(omp parallel for schedule(static) num_threads(::corotate::num_threads()) if ((cond) && ::corotate::num_threads() > 1))
#else
#define COROTATE_PARALLEL_FOR(cond)
#endif

namespace corotate {

// Whether a loop that COROTATE_PARALLEL_FOR would run in parallel when cond holds really gets
// more than one thread. A region whose if clause is false still enters the OpenMP runtime
// (a team of one is allocated and freed: about 0.24 us on this project's machine), so the
// loops a small body meets every step (about 15 per step of a 667-tet cage, 3 % of it) test
// this first and run a plain loop otherwise: parallel_for below, or, in a function compiled
// per CPU level (cpu_clones.hpp), an if around the pragma, since a region outlined from a
// helper would not be compiled for the clone's level.
inline bool runs_in_parallel(bool cond) { return cond && num_threads() > 1; }

// for (i = 0; i < n; ++i) body(i): on num_threads() threads when runs_in_parallel(cond),
// else a plain loop on the calling thread.
template <class Int, class Body>
void parallel_for(Int n, bool cond, const Body& body) {
  if (runs_in_parallel(cond)) {
    COROTATE_PARALLEL_FOR(true)
    for (Int i = 0; i < n; ++i) body(i);
  } else {
    for (Int i = 0; i < n; ++i) body(i);
  }
}

}  // namespace corotate
