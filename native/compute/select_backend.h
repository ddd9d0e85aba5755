// The backend rule every solver follows (DESIGN.md §3): "cpu" is the C++
// path; "opencl" must get a device or raise DeviceError; "auto" takes OpenCL
// when a GPU (or other accelerator) builds the kernels and otherwise uses
// C++, saying why.
//
// Why not an OpenCL CPU device under "auto" (issue 28): it runs the same
// loops on the same cores as the C++ path (OpenMP), with the kernel launch
// and buffer traffic on top. Measured with PoCL on a 2-core machine
// (medians of 3): sphere_map 1.08 s against 1.34 s at 100k faces, 0.15 s
// against 0.22 s at 25k; isometric_map 0.26 s against 0.34 s at 20k faces,
// 0.99 s against 1.12 s at 50k.
#pragma once

#include <memory>
#include <string>

#include "common/errors.h"
#include "compute/device.h"

namespace paramorph::compute {

/// make_cpu() -> unique_ptr<K>; make_opencl(std::string& why) -> unique_ptr<K>
/// or nullptr with `why`. `note` receives the fallback reason under "auto".
template <typename MakeCpu, typename MakeOpenCl>
auto select_backend(Backend backend, MakeCpu make_cpu, MakeOpenCl make_opencl, std::string& note)
    -> decltype(make_cpu()) {
  if (backend == Backend::Cpu) return make_cpu();
  if (backend == Backend::Auto) {
    const std::shared_ptr<Device> device = default_device();
    if (device && device->info().type == "cpu") {
      note = "the OpenCL device (" + device->description() +
             ") is a CPU, where the C++ path is faster; backend=\"opencl\" uses it";
      return make_cpu();
    }
  }
  std::string why;
  auto kernels = make_opencl(why);
  if (kernels) return kernels;
  PM_REQUIRE(backend != Backend::OpenCL, DeviceError,
             "backend=\"opencl\" requested but unavailable: ", why);
  note = "OpenCL unavailable (" + why + "), used the C++ backend";
  return make_cpu();
}

}  // namespace paramorph::compute
