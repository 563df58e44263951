// COROTATE_CPU_CLONES before a hot function's definition compiles it three times, for
// AVX-512, AVX2 with FMA and the x86-64 baseline, and the dynamic loader picks the best one
// the CPU runs (GCC's target_clones, an ifunc). Only loops written to vectorise (structure of
// arrays, no branches) gain from it; one build then runs fast on new CPUs and still runs on
// old ones, which -march=native (COROTATE_NATIVE) does not give. Elsewhere (other compilers,
// platforms without ifunc) it is empty: one baseline version.
#pragma once

// The levels are x86-64-v4 (AVX-512 F/BW/CD/DQ/VL) and v3 (AVX2, FMA, BMI), which the
// loader tests by feature bits (GCC 12 and later); a CPU model name ("arch=haswell") would be
// tested by model and fails in virtual machines that report a generic "Xeon Processor".
// COROTATE_CPU_CLONES_UP_TO_V3 (a benchmark build, CMake's COROTATE_CLONES_UP_TO_V3) leaves
// the AVX-512 clone out: on an AVX-512 machine the loader then picks the AVX2 one, which is
// what the same build runs on an AVX2 machine (Zen 3, say).
#if defined(__x86_64__) && defined(__linux__) && defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12 && \
    !defined(COROTATE_NO_CPU_CLONES)
#if defined(COROTATE_CPU_CLONES_UP_TO_V3)
#define COROTATE_CPU_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define COROTATE_CPU_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#endif
#define COROTATE_HAVE_CPU_CLONES 1
#else
#define COROTATE_CPU_CLONES
#define COROTATE_HAVE_CPU_CLONES 0
#endif

// For what a cloned function calls: inlined into each clone, so it is compiled for the
// clone's instruction set (a call would run the baseline version).
#if defined(__GNUC__)
#define COROTATE_CLONE_INLINE __attribute__((always_inline)) inline
#else
#define COROTATE_CLONE_INLINE inline
#endif

namespace corotate {

// Whether the hot loops run their AVX-512 clones on this CPU (false in a build without clones
// unless compiled for AVX-512, and in a COROTATE_CPU_CLONES_UP_TO_V3 build): code whose best
// vector width differs between AVX-512 and AVX2 (simd8.hpp's Double8 and Double4) picks by it.
bool cpu_runs_avx512_clones();

}  // namespace corotate
