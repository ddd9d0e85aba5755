// C++ backend of SphereKernels: OpenMP loops with the same per-vertex
// arithmetic as kernels/sphere.cl (serial on small meshes: common/parallel.h).
#include <Eigen/Dense>
#include <cmath>

#include "common/parallel.h"
#include "param/spherical/sphere_kernels.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::spherical {

namespace {

class CpuSphereKernels final : public SphereKernels {
 public:
  CpuSphereKernels(const SpringGraph& graph, const MatrixX3i& F) : g_(graph), F_(F) {}

  std::string backend() const override { return "cpu"; }
  std::string device() const override { return "C++ (OpenMP)"; }

  void begin_solve(const MatrixX3d& x) override {
    x_ = x;
    u_ = x;
    tmp_.resize(x.rows(), 3);
  }

  /// Weighted sum of the 1-ring of vertex i (ring_sum in kernels/sphere.cl).
  Eigen::Vector3d ring_sum(Index i, const MatrixX3d& u) const {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (Index k = g_.offsets[i]; k < g_.offsets[i + 1]; ++k)
      s += g_.weights[k] * u.row(g_.neighbors[k]).transpose();
    return s;
  }

  void jacobi(int sweeps, double omega) override {
    const Index n = g_.num_vertices();
    for (int s = 0; s < sweeps; ++s) {
#pragma omp parallel for schedule(static) if (worth_parallel(n))
      for (Index i = 0; i < n; ++i) {
        const Eigen::Vector3d xi = x_.row(i).transpose();
        const Eigen::Vector3d t =
            (1.0 - omega) * u_.row(i).transpose() + (omega / g_.degree[i]) * ring_sum(i, u_);
        const double lambda = xi.dot(t) - 1.0;
        tmp_.row(i) = (t - lambda * xi).transpose();
      }
      u_.swap(tmp_);
    }
  }

  double residual_squared() override {
    const Index n = g_.num_vertices();
    VectorXd row_residual(n);  // summed in order below: the same on every run
#pragma omp parallel for schedule(static) if (worth_parallel(n))
    for (Index i = 0; i < n; ++i) {
      const Eigen::Vector3d xi = x_.row(i).transpose();
      Eigen::Vector3d r = u_.row(i).transpose() - ring_sum(i, u_) / g_.degree[i];
      r -= xi.dot(r) * xi;
      row_residual[i] = r.squaredNorm();
    }
    return row_residual.sum();
  }

  void read_solution(MatrixX3d& u) override { u = u_; }
  void write_solution(const MatrixX3d& u) override { u_ = u; }

  void apply_projected_laplacian(const MatrixX3d& t, MatrixX3d& out) override {
    const Index n = g_.num_vertices();
    out.resize(n, 3);
#pragma omp parallel for schedule(static) if (worth_parallel(n))
    for (Index i = 0; i < n; ++i) {
      const Eigen::Vector3d xi = x_.row(i).transpose();
      Eigen::Vector3d r = g_.degree[i] * t.row(i).transpose() - ring_sum(i, t);
      r -= xi.dot(r) * xi;
      out.row(i) = r.transpose();
    }
  }

  Index count_flipped(const MatrixX3d& X) override { return Index(flipped_faces(X, F_).size()); }
  double energy(const MatrixX3d& X) override { return g_.energy(X); }

 private:
  const SpringGraph& g_;
  const MatrixX3i& F_;
  MatrixX3d x_, u_, tmp_;
};

}  // namespace

std::unique_ptr<SphereKernels> make_cpu_kernels(const SpringGraph& graph, const MatrixX3i& F) {
  return std::make_unique<CpuSphereKernels>(graph, F);
}

}  // namespace paramorph::spherical
