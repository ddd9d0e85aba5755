// Device-side sums and minima (kernels/reduce.cl): work-group partial sums in local
// memory, the few partials added on the host.
#pragma once

#include "compute/buffer.h"
#include "mesh/types.h"

namespace paramorph::compute {

/// Sum of values[0, n). n may be 0 or any size up to values.size().
double sum(Device& device, const Buffer<double>& values, Index n);
/// Minimum of values[0, n); +inf when n is 0.
double min(Device& device, const Buffer<double>& values, Index n);

}  // namespace paramorph::compute
