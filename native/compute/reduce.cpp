#include "compute/reduce.h"

#include <mutex>
#include <vector>

namespace paramorph::compute {

double sum(Device& device, const Buffer<double>& values, Index n) {
  if (n <= 0) return 0.0;
  constexpr std::size_t kGroup = 128, kGroups = 64;
  // One kernel object per device; setArg/enqueue are serialised by the lock.
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  cl::Kernel kernel(device.program("reduce.cl"), "partial_sums");
  cl::Buffer partials(device.context(), CL_MEM_READ_WRITE, kGroups * sizeof(double));
  kernel.setArg(0, cl_int(n));
  kernel.setArg(1, values.buffer());
  kernel.setArg(2, partials);
  kernel.setArg(3, cl::Local(kGroup * sizeof(double)));
  device.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(kGroup * kGroups),
                                      cl::NDRange(kGroup));
  std::vector<double> host(kGroups);
  device.queue().enqueueReadBuffer(partials, CL_TRUE, 0, kGroups * sizeof(double), host.data());
  double total = 0.0;
  for (double p : host) total += p;
  return total;
}

}  // namespace paramorph::compute
