#include "compute/device.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "common/errors.h"

namespace paramorph::compute {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back()))))
    s.pop_back();
  return s;
}

std::string type_name(cl_device_type type) {
  if (type & CL_DEVICE_TYPE_GPU) return "gpu";
  if (type & CL_DEVICE_TYPE_CPU) return "cpu";
  if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

/// Every device with its cl::Device handle (list_devices() drops the handles).
std::vector<std::pair<cl::Device, DeviceInfo>> enumerate() {
  std::vector<std::pair<cl::Device, DeviceInfo>> out;
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error&) {
    return out;  // no ICD loader platforms (CL_PLATFORM_NOT_FOUND_KHR)
  }
  for (auto& platform : platforms) {
    std::vector<cl::Device> devices;
    std::string platform_name;
    try {
      platform_name = trim(platform.getInfo<CL_PLATFORM_NAME>());
      platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;
    }
    for (auto& device : devices) {
      DeviceInfo info;
      info.platform = platform_name;
      try {
        info.name = trim(device.getInfo<CL_DEVICE_NAME>());
        info.type = type_name(device.getInfo<CL_DEVICE_TYPE>());
        info.version = trim(device.getInfo<CL_DEVICE_VERSION>());
        info.global_memory = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
        info.compute_units = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
        int major = 0, minor = 0;
        std::sscanf(info.version.c_str(), "OpenCL %d.%d", &major, &minor);
        if (!device.getInfo<CL_DEVICE_AVAILABLE>())
          info.reason = "device not available";
        else if (!device.getInfo<CL_DEVICE_COMPILER_AVAILABLE>())
          info.reason = "no OpenCL C compiler";
        else if (major * 10 + minor < 12)
          info.reason = "OpenCL 1.2 or newer required, device has " + info.version;
        else if (device.getInfo<CL_DEVICE_DOUBLE_FP_CONFIG>() == 0)
          info.reason = "no double precision (cl_khr_fp64)";
        info.usable = info.reason.empty();
      } catch (const cl::Error& e) {
        info.usable = false;
        info.reason = std::string("query failed: ") + e.what();
      }
      out.emplace_back(device, info);
    }
  }
  return out;
}

struct DefaultDevice {
  std::once_flag once;
  std::shared_ptr<Device> device;
  std::string error;
};

DefaultDevice& default_state() {
  static DefaultDevice state;
  return state;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> out;
  for (auto& [device, info] : enumerate()) out.push_back(info);
  return out;
}

long select_device(const std::vector<DeviceInfo>& devices, const char* filter) {
  std::vector<long> usable;
  for (std::size_t i = 0; i < devices.size(); ++i)
    if (devices[i].usable) usable.push_back(long(i));
  if (filter && *filter) {
    const std::string text(filter);
    if (std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); })) {
      const long k = std::atol(filter);
      return k < long(usable.size()) ? usable[k] : -1;
    }
    for (long i : usable)
      if (lower(devices[i].platform + " " + devices[i].name).find(lower(text)) != std::string::npos)
        return i;
    return -1;
  }
  for (long i : usable)
    if (devices[i].type == "gpu") return i;
  return usable.empty() ? -1 : usable.front();
}

std::shared_ptr<Device> default_device() {
  DefaultDevice& state = default_state();
  std::call_once(state.once, [&state] {
    const char* disable = std::getenv("PARAMORPH_OPENCL_DISABLE");
    if (disable && std::string(disable) == "1") {
      state.error = "OpenCL disabled by PARAMORPH_OPENCL_DISABLE=1";
      return;
    }
    auto found = enumerate();
    std::vector<DeviceInfo> infos;
    for (auto& entry : found) infos.push_back(entry.second);
    const char* filter = std::getenv("PARAMORPH_OPENCL_DEVICE");
    const long pick = select_device(infos, filter);
    if (pick < 0) {
      if (infos.empty()) {
        // No platform: no driver (ICD) registered with the loader, which is
        // how a minimal system or a container without a GPU looks.
        state.error =
            "no OpenCL driver found (no OpenCL platform: a GPU driver's OpenCL support or, for the CPU, "
            "pocl-opencl-icd provides one); paramorph runs on its CPU path";
      } else if (filter && *filter) {
        state.error = "no usable OpenCL device matches PARAMORPH_OPENCL_DEVICE=\"" + std::string(filter) + "\"";
      } else {
        state.error = "no usable OpenCL device found (";
        for (std::size_t i = 0; i < infos.size(); ++i)
          state.error += (i ? "; " : "") + infos[i].platform + " / " + infos[i].name + ": " + infos[i].reason;
        state.error += "); paramorph runs on its CPU path";
      }
      return;
    }
    try {
      state.device = std::make_shared<Device>(found[pick].first, found[pick].second);
    } catch (const cl::Error& e) {
      state.error = std::string("creating the OpenCL context failed: ") + e.what() + " (" +
                    std::to_string(e.err()) + ")";
    }
  });
  return state.device;
}

std::string default_device_error() {
  default_device();
  return default_state().error;
}

Device::Device(cl::Device device, DeviceInfo info)
    : device_(std::move(device)),
      info_(std::move(info)),
      context_(device_),
      queue_(context_, device_) {}

std::string Device::description() const { return info_.platform + " / " + info_.name; }

cl::Program& Device::program(const std::string& file) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = programs_.find(file);
  if (it != programs_.end()) return it->second;
  cl::Program program(context_, kernel_source(file));
  try {
    program.build(std::vector<cl::Device>{device_}, "-cl-std=CL1.2");
  } catch (const cl::Error&) {
    std::string log;
    try {
      log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_);
    } catch (const cl::Error&) {
    }
    throw DeviceError("building kernels/" + file + " failed on " + description() + ":\n" + log);
  }
  return programs_.emplace(file, std::move(program)).first->second;
}

std::string kernel_source(const std::string& file) {
  if (const char* dir = std::getenv("PARAMORPH_KERNEL_DIR"); dir && *dir) {
    std::ifstream in(std::string(dir) + "/" + file);
    if (in) {
      std::ostringstream text;
      text << in.rdbuf();
      return text.str();
    }
  }
  const auto& embedded = embedded_kernel_sources();
  auto it = embedded.find(file);
  if (it != embedded.end()) return it->second;
  std::string known;
  for (const auto& [name, text] : embedded) known += (known.empty() ? "" : ", ") + name;
  throw DeviceError("unknown kernel file \"" + file + "\" (embedded: " + known + ")");
}

Backend parse_backend(const std::string& name) {
  if (name == "auto") return Backend::Auto;
  if (name == "opencl") return Backend::OpenCL;
  if (name == "cpu") return Backend::Cpu;
  throw InvalidInputError("backend must be \"auto\", \"opencl\" or \"cpu\", got \"" + name + "\"");
}

std::string to_string(Backend backend) {
  switch (backend) {
    case Backend::Auto: return "auto";
    case Backend::OpenCL: return "opencl";
    case Backend::Cpu: return "cpu";
  }
  return "?";
}

}  // namespace paramorph::compute
