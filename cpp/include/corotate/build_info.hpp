// What this build of the core has: the optional backends it was compiled with and the
// instruction set its hot loops run at on this CPU (the clone the loader picks, cpu_clones.hpp).
#pragma once

#include <string>

namespace corotate {

struct BuildInfo {
  bool cholmod = false;   // SuiteSparse CHOLMOD for direct solves (else our supernodal Cholesky)
  bool openmp = false;    // OpenMP threads (else every loop on the calling thread)
  bool cpu_clones = false;  // hot loops compiled for several instruction sets
  std::string instruction_set;  // "x86-64-v4 (AVX-512)", "x86-64-v3 (AVX2, FMA)" or "baseline"
};

BuildInfo build_info();

}  // namespace corotate
