// The data-parallel work of the spherical solver behind one interface, with a
// C++ (OpenMP) and an OpenCL implementation running the same arithmetic
// (DESIGN.md §3 "backend"; thesis 3.4).
//
// The tangent-plane saddle-point problem of one outer step (thesis 3.3.1):
//   minimise E(u) = 1/2 sum_ij w_ij |u_i - u_j|^2  subject to  x_i · u_i = 1,
// with x the current map (unit vectors). Its residual is the tangential part
// of the normalised gradient, r_i = Π_i (u_i - sum_j w_ij u_j / D_i), Π_i = I - x_i x_iᵀ.
#pragma once

#include <memory>
#include <string>

#include "param/spherical/spring_graph.h"

namespace paramorph::spherical {

class SphereKernels {
 public:
  virtual ~SphereKernels() = default;

  /// Backend name ("cpu" or "opencl") and device description.
  virtual std::string backend() const = 0;
  virtual std::string device() const = 0;

  /// Starts a saddle-point solve about the map x: the frame is x and u = x.
  virtual void begin_solve(const MatrixX3d& x) = 0;
  /// Algorithm 3: `sweeps` damped Jacobi steps with the per-vertex multiplier
  /// λ_i = x_i · ũ_i - 1 and u_i = ũ_i - λ_i x_i, on the resident u.
  virtual void jacobi(int sweeps, double omega) = 0;
  /// Sum over vertices of |r_i|^2 for the resident u.
  virtual double residual_squared() = 0;
  /// Copies the resident u to the host.
  virtual void read_solution(MatrixX3d& u) = 0;
  /// Replaces the resident u (solvers that work on the host report through it).
  virtual void write_solution(const MatrixX3d& u) = 0;

  /// out = Π L t for tangent t (the projected operator of the PCG solver), with
  /// Π from the frame of the last begin_solve.
  virtual void apply_projected_laplacian(const MatrixX3d& t, MatrixX3d& out) = 0;

  /// Faces with orientation (b-a)x(c-a)·(a+b+c) <= 0, and the spring energy, for map X.
  virtual Index count_flipped(const MatrixX3d& X) = 0;
  virtual double energy(const MatrixX3d& X) = 0;
};

std::unique_ptr<SphereKernels> make_cpu_kernels(const SpringGraph& graph, const MatrixX3i& F);

/// nullptr with `why` filled when no OpenCL device is usable or the kernels do not build.
std::unique_ptr<SphereKernels> make_opencl_kernels(const SpringGraph& graph, const MatrixX3i& F,
                                                   std::string& why);

}  // namespace paramorph::spherical
