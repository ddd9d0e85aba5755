// A typed OpenCL buffer with blocking host transfers.
#pragma once

#include <cstddef>

#include "compute/device.h"

namespace paramorph::compute {

template <typename T>
class Buffer {
 public:
  Buffer(Device& device, std::size_t size)
      : device_(&device),
        size_(size),
        buffer_(device.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(size, 1) * sizeof(T)) {}
  Buffer(Device& device, const T* host, std::size_t size) : Buffer(device, size) { upload(host); }

  void upload(const T* host) {
    if (size_) device_->queue().enqueueWriteBuffer(buffer_, CL_TRUE, 0, size_ * sizeof(T), host);
  }
  void download(T* host) const {
    if (size_) device_->queue().enqueueReadBuffer(buffer_, CL_TRUE, 0, size_ * sizeof(T), host);
  }
  std::size_t size() const { return size_; }
  cl::Buffer& buffer() { return buffer_; }
  const cl::Buffer& buffer() const { return buffer_; }

 private:
  Device* device_;
  std::size_t size_;
  cl::Buffer buffer_;
};

}  // namespace paramorph::compute
