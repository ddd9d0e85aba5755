// The backend rule every solver follows (DESIGN.md §3): "cpu" is the C++
// path; "opencl" must get a device or raise ComputeError; "auto" takes OpenCL
// when a device builds the kernels and otherwise falls back to C++, saying why.
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
  std::string why;
  auto kernels = make_opencl(why);
  if (kernels) return kernels;
  PM_REQUIRE(backend != Backend::OpenCL, ComputeError,
             "backend=\"opencl\" requested but unavailable: ", why);
  note = "OpenCL unavailable (" + why + "), used the C++ backend";
  return make_cpu();
}

}  // namespace paramorph::compute
