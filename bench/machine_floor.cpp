// machine_floor: what this machine's memory bandwidth and FMA rate allow for the step's
// kernels, so the benchmark's numbers can be read against a floor (bench/README.md).
//
// Measures, on the calling thread: the streaming bandwidth (a triad a = b + s c over arrays
// far larger than the caches, over arrays that fit in L2, and over as many bytes as each
// matrix-vector product reads) and the double-precision FMA
// rate (independent multiply-add chains the compiler may vectorise). Then prints the floors
// of one CG iteration's block-sparse matrix-vector product on the benchmark beams: each
// 3x3 block is 72 bytes read once, 18 flops (9 FMAs).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
  return std::chrono::duration<double>(clock_type::now() - t0).count();
}

// Best of several triads over n doubles per array: bytes per second (3 arrays: 2 read, 1 written).
double triad_bandwidth(size_t n, int repeats) {
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = clock_type::now();
    for (size_t i = 0; i < n; ++i) a[i] = b[i] + 0.5 * c[i];
    best = std::min(best, seconds_since(t0));
    b[r % n] += a[(r * 7) % n];  // keep the loop from being optimised away
  }
  std::printf("  (checksum %g)\n", a[n / 2]);
  return 3.0 * 8.0 * n / best;
}

// Multiply-adds per second over 8 independent two-wide accumulators (SSE2, the ISA of the
// default build; no -march=native, so a multiply and an add rather than one FMA instruction).
// The empty asm keeps each accumulator live in its register so the loop cannot be folded.
double fma_rate(long iterations) {
  typedef double v2d __attribute__((vector_size(16)));
  v2d acc[8];
  for (int k = 0; k < 8; ++k) acc[k] = v2d{1.0 + 1e-9 * k, 1.0 - 1e-9 * k};
  const v2d x = {0.999999999, 0.999999998}, y = {1e-9, 2e-9};
  const auto t0 = clock_type::now();
  for (long i = 0; i < iterations; ++i)
    for (int k = 0; k < 8; ++k) {
      acc[k] = acc[k] * x + y;
      asm volatile("" : "+x"(acc[k]));
    }
  const double s = seconds_since(t0);
  double sum = 0;
  for (const v2d& v : acc) sum += v[0] + v[1];
  std::printf("  (checksum %g)\n", sum);
  return 16.0 * iterations / s;
}

}  // namespace

int main() {
  std::puts("machine_floor: one thread; best of several repeats");
  const double dram = triad_bandwidth(size_t(1) << 25, 5);  // 3 x 256 MB
  const double l3 = triad_bandwidth(size_t(1) << 16, 200);  // 3 x 512 KB
  const double fma = fma_rate(50'000'000);
  std::printf("stream triad, 768 MB: %.1f GB/s\nstream triad, 1.5 MB (in cache): %.1f GB/s\nFMA rate: %.2f G FMA/s\n",
              dram * 1e-9, l3 * 1e-9, fma * 1e-9);
  // The benchmark beams: nodes (10s+1)(2s+1)^2; a structured Kuhn mesh couples each interior
  // node to 14 neighbours and itself: about 15 blocks per node.
  std::puts("floor of one block-sparse matrix-vector product (72 bytes and 9 FMAs per 3x3 block):");
  for (int s : {4, 8}) {
    const double nodes = double(10 * s + 1) * (2 * s + 1) * (2 * s + 1), blocks = 15.0 * nodes;
    const double bytes = 72.0 * blocks + 2 * 24.0 * nodes;
    // The bandwidth of a triad over as many bytes as the product reads: at 15,360 tets the
    // matrix (3.7 MB) is larger than one core's L2, so the 1.5 MB figure would flatter it.
    const double bandwidth = bytes < 64e6 ? triad_bandwidth(size_t(bytes / 24), 50) : dram;
    std::printf("  %6d tets: %.1f MB, %.3f ms at the %.1f GB/s of a triad that size, %.3f ms at the FMA rate\n",
                240 * s * s * s, bytes * 1e-6, 1e3 * bytes / bandwidth, bandwidth * 1e-9, 1e3 * 9 * blocks / fma);
  }
  return 0;
}
