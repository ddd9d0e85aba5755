// C++ backend of IsometricKernels: OpenMP over faces, then over vertices
// (serial on small meshes: common/parallel.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel.h"
#include "param/planar/isometric_kernels.h"

namespace paramorph::planar {

namespace {

class CpuIsometricKernels final : public IsometricKernels {
 public:
  CpuIsometricKernels(const TriMesh& mesh, const IsometricFactors& factors)
      : F_(mesh.F()), corners_(mesh.vertex_corners()), factors_(factors),
        face_energy_(mesh.num_faces()), corner_gradient_(3 * mesh.num_faces(), 2) {}

  std::string backend() const override { return "cpu"; }
  std::string device() const override { return "C++ (OpenMP)"; }

  double energy(const MatrixX2d& uv, MatrixX2d* gradient) override {
    const Index m = Index(F_.rows());
    const bool want_gradient = gradient != nullptr;
    const bool parallel = worth_parallel(m);
#pragma omp parallel for schedule(static) if (parallel)
    for (Index f = 0; f < m; ++f) {
      Eigen::Vector2d g[3];
      face_energy_[f] = face_isometric_energy(
          factors_.factors(f, 0), factors_.factors(f, 1), factors_.factors(f, 2),
          factors_.area[f], uv.row(F_(f, 0)), uv.row(F_(f, 1)), uv.row(F_(f, 2)),
          want_gradient ? g : nullptr);
      if (want_gradient && std::isfinite(face_energy_[f]))
        for (int k = 0; k < 3; ++k) corner_gradient_.row(3 * f + k) = g[k].transpose();
    }
    // A fixed-order sum: the same value on every run and thread count.
    double total = 0.0;
    for (Index f = 0; f < m; ++f) total += face_energy_[f];
    if (!std::isfinite(total) || !gradient) return total;
    const Index n = Index(uv.rows());
    gradient->resize(n, 2);
#pragma omp parallel for schedule(static) if (parallel)
    for (Index v = 0; v < n; ++v) {
      Eigen::RowVector2d sum = Eigen::RowVector2d::Zero();
      for (Index k = corners_.begin(v); k < corners_.end(v); ++k)
        sum += corner_gradient_.row(corners_.items[k]);
      gradient->row(v) = sum;
    }
    return total;
  }

  double max_feasible_step(const MatrixX2d& uv, const MatrixX2d& d) override {
    const Index m = Index(F_.rows());
    double best = std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(static) reduction(min : best) if (worth_parallel(m))
    for (Index f = 0; f < m; ++f)
      best = std::min(best, face_first_inversion(uv.row(F_(f, 0)), uv.row(F_(f, 1)),
                                                 uv.row(F_(f, 2)), d.row(F_(f, 0)),
                                                 d.row(F_(f, 1)), d.row(F_(f, 2))));
    return best;
  }

 private:
  const MatrixX3i& F_;
  const Csr& corners_;
  const IsometricFactors& factors_;
  VectorXd face_energy_;
  MatrixX2d corner_gradient_;  ///< row 3f + k: face f's gradient at its corner k
};

}  // namespace

std::unique_ptr<IsometricKernels> make_cpu_isometric_kernels(const TriMesh& mesh,
                                                             const IsometricFactors& factors) {
  return std::make_unique<CpuIsometricKernels>(mesh, factors);
}

}  // namespace paramorph::planar
