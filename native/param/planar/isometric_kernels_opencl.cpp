// OpenCL backend of IsometricKernels (kernels/planar.cl). The mesh, factors
// and CSR live on the device; each call uploads uv (and d), and reads back the
// gradient and the reduced energy or step.
#include <algorithm>

#include "common/errors.h"
#include "compute/device.h"
#include "compute/reduce.h"
#include "param/planar/isometric_kernels.h"

namespace paramorph::planar {

namespace {

constexpr std::size_t kGroup = 64;

cl::NDRange global_range(Index count) {
  return cl::NDRange(((std::size_t(count) + kGroup - 1) / kGroup) * kGroup);
}

class OpenClIsometricKernels final : public IsometricKernels {
 public:
  OpenClIsometricKernels(std::shared_ptr<compute::Device> device, const TriMesh& mesh,
                         const IsometricFactors& factors)
      : dev_(std::move(device)), n_(mesh.num_vertices()), m_(mesh.num_faces()) {
    auto& ctx = dev_->context();
    cl::Program& program = dev_->program("planar.cl");
    face_energy_ = cl::Kernel(program, "face_energy");
    gather_ = cl::Kernel(program, "gather_gradient");
    inversion_ = cl::Kernel(program, "face_first_inversion");
    auto constant = [&](const void* host, std::size_t bytes) {
      return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, std::max<std::size_t>(bytes, 8),
                        const_cast<void*>(host));
    };
    const Csr& corners = mesh.vertex_corners();
    faces_ = constant(mesh.F().data(), std::size_t(mesh.F().size()) * sizeof(Index));
    factors_ = constant(factors.factors.data(), std::size_t(factors.factors.size()) * sizeof(double));
    area_ = constant(factors.area.data(), std::size_t(m_) * sizeof(double));
    offsets_ = constant(corners.offsets.data(), corners.offsets.size() * sizeof(Index));
    corners_ = constant(corners.items.data(), corners.items.size() * sizeof(Index));
    auto scratch = [&](std::size_t doubles) {
      return cl::Buffer(ctx, CL_MEM_READ_WRITE, std::max<std::size_t>(doubles, 1) * sizeof(double));
    };
    uv_ = scratch(2 * std::size_t(n_));
    d_ = scratch(2 * std::size_t(n_));
    gradient_ = scratch(2 * std::size_t(n_));
    corner_gradient_ = scratch(6 * std::size_t(m_));
    per_face_ = std::make_unique<compute::Buffer<double>>(*dev_, std::size_t(m_));
  }

  std::string backend() const override { return "opencl"; }
  std::string device() const override { return dev_->description(); }

  double energy(const MatrixX2d& uv, MatrixX2d* gradient) override {
    write(uv_, uv);
    face_energy_.setArg(0, cl_int(m_));
    face_energy_.setArg(1, faces_);
    face_energy_.setArg(2, factors_);
    face_energy_.setArg(3, area_);
    face_energy_.setArg(4, uv_);
    face_energy_.setArg(5, per_face_->buffer());
    face_energy_.setArg(6, corner_gradient_);
    face_energy_.setArg(7, cl_int(gradient ? 1 : 0));
    run(face_energy_, m_);
    const double total = compute::sum(*dev_, *per_face_, m_);
    if (!std::isfinite(total) || !gradient) return total;
    gather_.setArg(0, cl_int(n_));
    gather_.setArg(1, offsets_);
    gather_.setArg(2, corners_);
    gather_.setArg(3, corner_gradient_);
    gather_.setArg(4, gradient_);
    run(gather_, n_);
    gradient->resize(n_, 2);
    dev_->queue().enqueueReadBuffer(gradient_, CL_TRUE, 0, std::size_t(2 * n_) * sizeof(double),
                                    gradient->data());
    return total;
  }

  double max_feasible_step(const MatrixX2d& uv, const MatrixX2d& d) override {
    write(uv_, uv);
    write(d_, d);
    inversion_.setArg(0, cl_int(m_));
    inversion_.setArg(1, faces_);
    inversion_.setArg(2, uv_);
    inversion_.setArg(3, d_);
    inversion_.setArg(4, per_face_->buffer());
    run(inversion_, m_);
    return compute::min(*dev_, *per_face_, m_);
  }

 private:
  void run(cl::Kernel& k, Index count) {
    if (count == 0) return;
    dev_->queue().enqueueNDRangeKernel(k, cl::NullRange, global_range(count), cl::NDRange(kGroup));
  }
  void write(cl::Buffer& b, const MatrixX2d& a) {
    PM_REQUIRE(a.rows() == n_, InvalidInputError, "expected ", n_, " rows, got ", a.rows());
    dev_->queue().enqueueWriteBuffer(b, CL_TRUE, 0, std::size_t(a.size()) * sizeof(double), a.data());
  }

  std::shared_ptr<compute::Device> dev_;
  Index n_, m_;
  cl::Kernel face_energy_, gather_, inversion_;
  cl::Buffer faces_, factors_, area_, offsets_, corners_, uv_, d_, gradient_, corner_gradient_;
  std::unique_ptr<compute::Buffer<double>> per_face_;
};

}  // namespace

std::unique_ptr<IsometricKernels> make_opencl_isometric_kernels(const TriMesh& mesh,
                                                                const IsometricFactors& factors,
                                                                std::string& why) {
  auto device = compute::default_device();
  if (!device) {
    why = "no usable OpenCL device (" + compute::default_device_error() + ")";
    return nullptr;
  }
  try {
    return std::make_unique<OpenClIsometricKernels>(device, mesh, factors);
  } catch (const ComputeError& e) {
    why = e.what();
  } catch (const cl::Error& e) {
    why = std::string("OpenCL error in ") + e.what() + " (" + std::to_string(e.err()) + ")";
  }
  return nullptr;
}

}  // namespace paramorph::planar
