// OpenCL layer (compute/): embedded kernels, the override directory, device
// selection, build errors with their log, the device reduction.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>

#include "common/errors.h"
#include "compute/device.h"
#include "compute/reduce.h"

using namespace paramorph;
using namespace paramorph::compute;
namespace fs = std::filesystem;

namespace {
struct KernelDir {  // a temporary PARAMORPH_KERNEL_DIR
  fs::path path = fs::temp_directory_path() / ("paramorph_kernels_" + std::to_string(::getpid()));
  KernelDir() { fs::create_directories(path); setenv("PARAMORPH_KERNEL_DIR", path.c_str(), 1); }
  ~KernelDir() { unsetenv("PARAMORPH_KERNEL_DIR"); fs::remove_all(path); }
  void write(const std::string& file, const std::string& text) { std::ofstream(path / file) << text; }
};
}  // namespace

TEST(Kernels, EmbeddedAndOverridable) {
  EXPECT_EQ(embedded_kernel_sources().count("reduce.cl"), 1u);
  EXPECT_EQ(embedded_kernel_sources().count("sphere.cl"), 1u);
  EXPECT_NE(kernel_source("reduce.cl").find("partial_sums"), std::string::npos);
  {
    KernelDir dir;
    dir.write("reduce.cl", "// overridden\n");
    EXPECT_EQ(kernel_source("reduce.cl"), "// overridden\n");
    EXPECT_NE(kernel_source("sphere.cl").find("jacobi_sweep"), std::string::npos);  // falls back
  }
  EXPECT_THROW(kernel_source("missing.cl"), DeviceError);
}

TEST(Devices, SelectionByFilter) {
  std::vector<DeviceInfo> d(3);
  d[0] = {"Portable Computing Language", "pthread-cpu", "cpu", "OpenCL 3.0", true, "", 0, 2};
  d[1] = {"NVIDIA CUDA", "H100", "gpu", "OpenCL 3.0", true, "", 0, 132};
  d[2] = {"Old", "card", "gpu", "OpenCL 1.1", false, "OpenCL 1.2 or newer required", 0, 1};
  EXPECT_EQ(select_device(d, nullptr), 1);   // a usable GPU first
  EXPECT_EQ(select_device(d, "pocl"), -1);   // substring of "platform name"
  EXPECT_EQ(select_device(d, "portable"), 0);
  EXPECT_EQ(select_device(d, "0"), 0);       // index among usable devices
  EXPECT_EQ(select_device(d, "1"), 1);
  EXPECT_EQ(select_device(d, "2"), -1);      // the rejected device is not counted
  EXPECT_EQ(select_device(d, "card"), -1);   // nor matched
  d[1].usable = false;
  EXPECT_EQ(select_device(d, nullptr), 0);
  EXPECT_EQ(select_device({}, nullptr), -1);
  EXPECT_EQ(parse_backend("cpu"), Backend::Cpu);
  EXPECT_THROW(parse_backend("cuda"), InvalidInputError);
}

TEST(Devices, ListedDevicesExplainRejections) {
  for (const auto& d : list_devices()) EXPECT_EQ(d.usable, d.reason.empty()) << d.name;
}

TEST(Reduce, MatchesTheHostSum) {
  auto device = default_device();
  if (!device) GTEST_SKIP() << default_device_error();
  for (Index n : {0, 1, 255, 256, 257, 100003}) {
    std::vector<double> values(std::max<Index>(n, 1));
    for (Index i = 0; i < n; ++i) values[i] = std::sin(0.1 * i) + 1e-3 * i;
    Buffer<double> buffer(*device, values.data(), values.size());
    const double expected = std::accumulate(values.begin(), values.begin() + n, 0.0);
    EXPECT_NEAR(sum(*device, buffer, n), expected, 1e-12 * std::max(1.0, std::abs(expected))) << n;
  }
}

TEST(Reduce, MatchesTheHostMinimum) {
  auto device = default_device();
  if (!device) GTEST_SKIP() << default_device_error();
  for (Index n : {0, 1, 255, 257, 100003}) {
    std::vector<double> values(std::max<Index>(n, 1), 5.0);
    for (Index i = 0; i < n; ++i) values[i] = 2.0 + std::sin(0.37 * i);
    if (n > 0) values[n / 3] = -1.25;  // the minimum, somewhere inside
    values.push_back(-100.0);          // past n: must be ignored
    Buffer<double> buffer(*device, values.data(), values.size());
    const double expected = n > 0 ? -1.25 : std::numeric_limits<double>::infinity();
    EXPECT_EQ(compute::min(*device, buffer, n), expected) << n;
  }
}

TEST(Programs, CachedAndBuildErrorsCarryTheLog) {
  auto device = default_device();
  if (!device) GTEST_SKIP() << default_device_error();
  cl::Program& a = device->program("reduce.cl");
  cl::Program& b = device->program("reduce.cl");
  EXPECT_EQ(a(), b());
  KernelDir dir;
  dir.write("broken.cl", "__kernel void k(__global int* x) { x[0] = undefined_name; }\n");
  try {
    device->program("broken.cl");
    FAIL() << "built a broken kernel";
  } catch (const DeviceError& e) {  // a ComputeError that is the device's fault
    const std::string what = e.what();
    EXPECT_NE(what.find("broken.cl"), std::string::npos);
    EXPECT_NE(what.find("undefined_name"), std::string::npos) << what;
  }
}
