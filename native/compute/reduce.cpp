#include "compute/reduce.h"

#include <algorithm>
#include <limits>
#include <mutex>
#include <vector>

namespace paramorph::compute {

namespace {

/// Runs `kernel_name` of reduce.cl: one partial per work-group, read back.
std::vector<double> partials(Device& device, const char* kernel_name, const Buffer<double>& values,
                             Index n) {
  constexpr std::size_t kGroup = 128, kGroups = 64;
  // One kernel object per call; setArg/enqueue are serialised by the lock.
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  cl::Kernel kernel(device.program("reduce.cl"), kernel_name);
  cl::Buffer out(device.context(), CL_MEM_READ_WRITE, kGroups * sizeof(double));
  kernel.setArg(0, cl_int(n));
  kernel.setArg(1, values.buffer());
  kernel.setArg(2, out);
  kernel.setArg(3, cl::Local(kGroup * sizeof(double)));
  device.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(kGroup * kGroups),
                                      cl::NDRange(kGroup));
  std::vector<double> host(kGroups);
  device.queue().enqueueReadBuffer(out, CL_TRUE, 0, kGroups * sizeof(double), host.data());
  return host;
}

}  // namespace

double sum(Device& device, const Buffer<double>& values, Index n) {
  if (n <= 0) return 0.0;
  double total = 0.0;
  for (double p : partials(device, "partial_sums", values, n)) total += p;
  return total;
}

double min(Device& device, const Buffer<double>& values, Index n) {
  if (n <= 0) return std::numeric_limits<double>::infinity();
  const std::vector<double> p = partials(device, "partial_mins", values, n);
  return *std::min_element(p.begin(), p.end());
}

}  // namespace paramorph::compute
