#include "corotate/parallel.hpp"

#include <atomic>
#include <string>

#include "corotate/common.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace corotate {

namespace {
std::atomic<int> thread_count{1};
}

bool have_openmp() {
#ifdef _OPENMP
  return true;
#else
  return false;
#endif
}

int available_threads() {
#ifdef _OPENMP
  return omp_get_num_procs();
#else
  return 1;
#endif
}

int num_threads() { return thread_count.load(std::memory_order_relaxed); }

void set_num_threads(int n) {
  if (n < 1) throw InvalidInput("the thread count must be at least 1, got " + std::to_string(n));
  if (n > 1 && !have_openmp())
    throw InvalidInput("corotate was built without OpenMP: it runs on one thread only (asked for " + std::to_string(n) +
                       ")");
  thread_count.store(n, std::memory_order_relaxed);
}

}  // namespace corotate
