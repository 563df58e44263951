#include "corotate/build_info.hpp"

#include "corotate/cpu_clones.hpp"
#include "corotate/parallel.hpp"
#include "corotate/solvers/sparse_cholesky.hpp"

namespace corotate {

bool cpu_runs_avx512_clones() {
#if COROTATE_HAVE_CPU_CLONES && !defined(COROTATE_CPU_CLONES_UP_TO_V3)
  // The same test by feature bits the loader makes to pick a clone.
  static const bool avx512 = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("x86-64-v4");
  }();
  return avx512;
#elif defined(__AVX512F__) && !COROTATE_HAVE_CPU_CLONES
  return true;
#else
  return false;
#endif
}

BuildInfo build_info() {
  BuildInfo info;
  info.cholmod = SparseCholesky::have_cholmod();
  info.openmp = have_openmp();
#if COROTATE_HAVE_CPU_CLONES
  info.cpu_clones = true;
  __builtin_cpu_init();
  if (cpu_runs_avx512_clones()) info.instruction_set = "x86-64-v4 (AVX-512)";
  else if (__builtin_cpu_supports("x86-64-v3")) info.instruction_set = "x86-64-v3 (AVX2, FMA)";
  else info.instruction_set = "baseline";
#elif defined(__AVX512F__)  // one version, compiled for what the compiler was told
  info.instruction_set = "x86-64-v4 (AVX-512), compiled in";
#elif defined(__AVX2__)
  info.instruction_set = "x86-64-v3 (AVX2, FMA), compiled in";
#else
  info.instruction_set = "baseline";
#endif
  return info;
}

}  // namespace corotate
