#include "corotate/build_info.hpp"

#include "corotate/cpu_clones.hpp"
#include "corotate/parallel.hpp"
#include "corotate/solvers/sparse_cholesky.hpp"

namespace corotate {

BuildInfo build_info() {
  BuildInfo info;
  info.cholmod = SparseCholesky::have_cholmod();
  info.openmp = have_openmp();
#if COROTATE_HAVE_CPU_CLONES
  // The same test by feature bits the loader makes to pick a clone.
  info.cpu_clones = true;
  __builtin_cpu_init();
#if defined(COROTATE_CPU_CLONES_UP_TO_V3)
  const bool v4 = false;  // (no AVX-512 clone in this build)
#else
  const bool v4 = __builtin_cpu_supports("x86-64-v4");
#endif
  if (v4) info.instruction_set = "x86-64-v4 (AVX-512)";
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
