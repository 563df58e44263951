#include "corotate/fem/batch_scatter.hpp"

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
  add_batch_product_blocks<4, 16>(batch, count, targets, values);
}

}  // namespace corotate
