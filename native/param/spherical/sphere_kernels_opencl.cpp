// OpenCL backend of SphereKernels (kernels/sphere.cl): the per-vertex and
// per-face work runs on the device; u stays resident there during Jacobi
// sweeps so the host only reads a residual every `check_every` sweeps.
#include <cmath>

#include "common/errors.h"
#include "compute/device.h"
#include "compute/reduce.h"
#include "param/spherical/sphere_kernels.h"

namespace paramorph::spherical {

namespace {

constexpr std::size_t kGroup = 64;

cl::NDRange global_range(Index count) {
  return cl::NDRange(((std::size_t(count) + kGroup - 1) / kGroup) * kGroup);
}

class OpenClSphereKernels final : public SphereKernels {
 public:
  OpenClSphereKernels(std::shared_ptr<compute::Device> device, const SpringGraph& graph,
                      const MatrixX3i& F)
      : dev_(std::move(device)), n_(graph.num_vertices()), m_(Index(F.rows())) {
    auto& ctx = dev_->context();
    cl::Program& program = dev_->program("sphere.cl");
    jacobi_ = cl::Kernel(program, "jacobi_sweep");
    residual_ = cl::Kernel(program, "residual_terms");
    laplacian_ = cl::Kernel(program, "projected_laplacian");
    energy_ = cl::Kernel(program, "energy_terms");
    flipped_ = cl::Kernel(program, "flipped_flags");

    auto make = [&](const void* host, std::size_t bytes) {
      return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, std::max<std::size_t>(bytes, 8),
                        const_cast<void*>(host));
    };
    offsets_ = make(graph.offsets.data(), graph.offsets.size() * sizeof(Index));
    neighbors_ = make(graph.neighbors.data(), graph.neighbors.size() * sizeof(Index));
    weights_ = make(graph.weights.data(), graph.weights.size() * sizeof(double));
    degree_ = make(graph.degree.data(), std::size_t(n_) * sizeof(double));
    faces_ = make(F.data(), std::size_t(F.size()) * sizeof(Index));
    const std::size_t vec = std::max<std::size_t>(std::size_t(3 * n_) * sizeof(double), 8);
    x_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, vec);
    u_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, vec);
    tmp_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, vec);
    scratch_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, vec);
    terms_ = std::make_unique<compute::Buffer<double>>(*dev_, std::size_t(std::max(n_, m_)));
  }

  std::string backend() const override { return "opencl"; }
  std::string device() const override { return dev_->description(); }

  void begin_solve(const MatrixX3d& x) override {
    write(x_, x);
    write(u_, x);
  }

  void jacobi(int sweeps, double omega) override {
    for (int s = 0; s < sweeps; ++s) {
      set_graph_args(jacobi_);
      jacobi_.setArg(5, x_);
      jacobi_.setArg(6, u_);
      jacobi_.setArg(7, tmp_);
      jacobi_.setArg(8, omega);
      run(jacobi_, n_);
      std::swap(u_, tmp_);
    }
  }

  double residual_squared() override {
    set_graph_args(residual_);
    residual_.setArg(5, x_);
    residual_.setArg(6, u_);
    residual_.setArg(7, terms_->buffer());
    run(residual_, n_);
    return compute::sum(*dev_, *terms_, n_);
  }

  void read_solution(MatrixX3d& u) override { read(u_, u); }
  void write_solution(const MatrixX3d& u) override { write(u_, u); }

  void apply_projected_laplacian(const MatrixX3d& t, MatrixX3d& out) override {
    write(scratch_, t);
    set_graph_args(laplacian_);
    laplacian_.setArg(5, x_);
    laplacian_.setArg(6, scratch_);
    laplacian_.setArg(7, tmp_);
    run(laplacian_, n_);
    read(tmp_, out);
  }

  Index count_flipped(const MatrixX3d& X) override {
    write(scratch_, X);
    flipped_.setArg(0, cl_int(m_));
    flipped_.setArg(1, faces_);
    flipped_.setArg(2, scratch_);
    flipped_.setArg(3, terms_->buffer());
    run(flipped_, m_);
    return Index(std::llround(compute::sum(*dev_, *terms_, m_)));
  }

  double energy(const MatrixX3d& X) override {
    write(scratch_, X);
    energy_.setArg(0, cl_int(n_));
    energy_.setArg(1, offsets_);
    energy_.setArg(2, neighbors_);
    energy_.setArg(3, weights_);
    energy_.setArg(4, scratch_);
    energy_.setArg(5, terms_->buffer());
    run(energy_, n_);
    return compute::sum(*dev_, *terms_, n_);
  }

 private:
  void set_graph_args(cl::Kernel& k) {
    k.setArg(0, cl_int(n_));
    k.setArg(1, offsets_);
    k.setArg(2, neighbors_);
    k.setArg(3, weights_);
    k.setArg(4, degree_);
  }
  void run(cl::Kernel& k, Index count) {
    if (count == 0) return;
    dev_->queue().enqueueNDRangeKernel(k, cl::NullRange, global_range(count), cl::NDRange(kGroup));
  }
  void write(cl::Buffer& b, const MatrixX3d& a) {
    dev_->queue().enqueueWriteBuffer(b, CL_TRUE, 0, std::size_t(a.size()) * sizeof(double), a.data());
  }
  void read(cl::Buffer& b, MatrixX3d& a) {
    a.resize(n_, 3);
    dev_->queue().enqueueReadBuffer(b, CL_TRUE, 0, std::size_t(a.size()) * sizeof(double), a.data());
  }

  std::shared_ptr<compute::Device> dev_;
  Index n_, m_;
  cl::Kernel jacobi_, residual_, laplacian_, energy_, flipped_;
  cl::Buffer offsets_, neighbors_, weights_, degree_, faces_, x_, u_, tmp_, scratch_;
  std::unique_ptr<compute::Buffer<double>> terms_;
};

}  // namespace

std::unique_ptr<SphereKernels> make_opencl_kernels(const SpringGraph& graph, const MatrixX3i& F,
                                                   std::string& why) {
  auto device = compute::default_device();
  if (!device) {
    why = "no usable OpenCL device (" + compute::default_device_error() + ")";
    return nullptr;
  }
  try {
    return std::make_unique<OpenClSphereKernels>(device, graph, F);
  } catch (const ComputeError& e) {
    why = e.what();
  } catch (const cl::Error& e) {
    why = std::string("OpenCL error in ") + e.what() + " (" + std::to_string(e.err()) + ")";
  }
  return nullptr;
}

}  // namespace paramorph::spherical
