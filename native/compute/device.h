// OpenCL devices: discovery, selection, per-context program cache (DESIGN.md §3, §6).
//
// The module builds and runs without any OpenCL platform: list_devices() then
// returns an empty list and default_device() returns nullptr, and every solver
// falls back to its C++ path.
//
// Selection is reproducible through environment variables:
//   PARAMORPH_OPENCL_DEVICE   case-insensitive substring matched against
//                             "<platform name> <device name>"; or an integer
//                             index into the usable devices.
//   PARAMORPH_OPENCL_DISABLE  when set to 1, no device is used at all.
//   PARAMORPH_KERNEL_DIR      load kernels/<name>.cl from this directory instead
//                             of the sources embedded at build time.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "compute/opencl.h"

namespace paramorph::compute {

/// One device as found, usable or not.
struct DeviceInfo {
  std::string platform;
  std::string name;
  std::string type;     ///< "cpu", "gpu", "accelerator", "other"
  std::string version;  ///< CL_DEVICE_VERSION
  bool usable = false;
  std::string reason;   ///< why it was rejected (empty when usable)
  std::size_t global_memory = 0;
  unsigned compute_units = 0;
};

/// Every platform/device found; rejected ones say why (no double precision,
/// OpenCL < 1.2, not available, no compiler). Never throws.
std::vector<DeviceInfo> list_devices();

/// A usable device with its context, queue and compiled-program cache.
class Device {
 public:
  Device(cl::Device device, DeviceInfo info);

  const DeviceInfo& info() const { return info_; }
  /// "platform / device name" for result structs.
  std::string description() const;
  cl::Context& context() { return context_; }
  cl::CommandQueue& queue() { return queue_; }
  const cl::Device& device() const { return device_; }

  /// The program built from kernels/<file> (e.g. "sphere.cl"), compiled once per
  /// device and cached. Throws DeviceError with the device's build log.
  cl::Program& program(const std::string& file);

 private:
  cl::Device device_;
  DeviceInfo info_;
  cl::Context context_;
  cl::CommandQueue queue_;
  std::mutex mutex_;
  std::map<std::string, cl::Program> programs_;
};

/// Index into `devices` of the one to use: `filter` (PARAMORPH_OPENCL_DEVICE)
/// as an integer counts usable devices only, otherwise it is a
/// case-insensitive substring of "platform device"; without a filter a usable
/// GPU is preferred, then any usable device. -1 when nothing matches.
long select_device(const std::vector<DeviceInfo>& devices, const char* filter);

/// The device selected by the environment (see above), created once and
/// shared; nullptr when no usable device exists or OpenCL is disabled
/// (default_device_error() then says why).
std::shared_ptr<Device> default_device();
std::string default_device_error();

/// Source text of kernels/<file>: from PARAMORPH_KERNEL_DIR when set and the
/// file exists there, else the embedded copy. Throws DeviceError if unknown.
std::string kernel_source(const std::string& file);

/// Generated at build time from kernels/*.cl (cmake/embed_kernels.cmake).
const std::map<std::string, std::string>& embedded_kernel_sources();

/// Backend choice shared by all solvers.
enum class Backend { Auto, OpenCL, Cpu };
Backend parse_backend(const std::string& name);  ///< throws InvalidInputError
std::string to_string(Backend backend);

}  // namespace paramorph::compute
