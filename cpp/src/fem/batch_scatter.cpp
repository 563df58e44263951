#include "corotate/fem/batch_scatter.hpp"

// The clones below inline simd8.hpp's helpers: no call passes a vector (see there).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace corotate {

COROTATE_CPU_CLONES void add_batch_blocks(const ForceStiffnessBatch<4, 16>& batch, int count, const int* ids,
                                          double* values) {
  add_batch_blocks<4, 16>(batch, count, ids, values);
}

COROTATE_CPU_CLONES void add_batch_product_blocks(const ForceStiffnessBatch<4, 16>& batch, int count,
                                                  const ProductBlockTargets<4>* targets, double* values) {
  add_batch_product_blocks<4, 16>(batch, count, targets, values);
}

COROTATE_CPU_CLONES void add_batch_product_blocks(const ForceStiffnessBatch<4, 16>& batch, int count,
                                                  const ProductBlockTargets<4>* targets, float* values) {
#if defined(COROTATE_HAVE_FLOAT8)
  add_batch_product_blocks_vectorised<4, 16>(batch, count, targets, values);
#else
  add_batch_product_blocks<4, 16>(batch, count, targets, values);
#endif
}

}  // namespace corotate
