// IsometricKernels: the OpenMP scatter/gather and the OpenCL kernels against
// the serial reference (param/planar/isometric_kernels, kernels/planar.cl).
#include <gtest/gtest.h>

#include <cmath>

#include "compute/device.h"
#include "param/planar/isometric_kernels.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::planar;

namespace {

struct Case {
  TriMesh mesh;
  IsometricFactors factors;
  MatrixX2d uv, direction;
};

/// A bumpy grid mapped by its (x, y) projection, slightly sheared so no face
/// is at the isometry, and a smooth direction that inverts faces eventually.
Case make_case() {
  auto [V, F] = test_meshes::bumpy_grid(24);
  Case c{TriMesh(V, F), isometric_factors(V, F), MatrixX2d(V.rows(), 2), MatrixX2d(V.rows(), 2)};
  for (Index v = 0; v < V.rows(); ++v) {
    const double x = V(v, 0), y = V(v, 1);
    c.uv.row(v) << x + 0.1 * y * y, 0.9 * y;
    c.direction.row(v) << std::sin(5 * x + 2 * y), std::cos(3 * x * y);
  }
  return c;
}

void expect_matches_reference(IsometricKernels& kernels, const Case& c, double tol) {
  const MatrixX3i& F = c.mesh.F();
  MatrixX2d reference_gradient, gradient;
  const double reference = isometric_energy(c.factors, F, c.uv, &reference_gradient);
  const double energy = kernels.energy(c.uv, &gradient);
  EXPECT_NEAR(energy, reference, tol * reference) << kernels.backend();
  EXPECT_LT((gradient - reference_gradient).cwiseAbs().maxCoeff(),
            tol * reference_gradient.cwiseAbs().maxCoeff()) << kernels.backend();
  EXPECT_NEAR(kernels.energy(c.uv, nullptr), reference, tol * reference);
  const double step = kernels.max_feasible_step(c.uv, c.direction);
  ASSERT_TRUE(std::isfinite(step));
  EXPECT_NEAR(step, max_feasible_step(F, c.uv, c.direction), tol * step) << kernels.backend();
  // Past the bound a face is inverted and the energy is +inf on every backend.
  EXPECT_TRUE(std::isinf(kernels.energy(c.uv + 1.01 * step * c.direction, &gradient)));
  EXPECT_TRUE(std::isfinite(kernels.energy(c.uv + 0.99 * step * c.direction, nullptr)));
  EXPECT_TRUE(std::isinf(kernels.max_feasible_step(c.uv, MatrixX2d::Zero(c.uv.rows(), 2))));
}

}  // namespace

TEST(IsometricKernels, CpuScatterGatherMatchesTheSerialReference) {
  const Case c = make_case();
  auto kernels = make_cpu_isometric_kernels(c.mesh, c.factors);
  EXPECT_EQ(kernels->backend(), "cpu");
  expect_matches_reference(*kernels, c, 1e-12);
}

TEST(IsometricKernels, OpenClMatchesTheSerialReference) {
  if (!compute::default_device()) GTEST_SKIP() << compute::default_device_error();
  const Case c = make_case();
  std::string why;
  auto kernels = make_opencl_isometric_kernels(c.mesh, c.factors, why);
  ASSERT_TRUE(kernels) << why;
  EXPECT_EQ(kernels->backend(), "opencl");
  expect_matches_reference(*kernels, c, 1e-11);
}
