// The data-parallel work of the planar solver behind one interface, with a
// C++ (OpenMP) and an OpenCL implementation of the same algorithm (thesis
// 2.3.2; DESIGN.md §3 "backend", §4.1).
//
// Gradient: a per-face pass writes each face's energy and its three corner
// gradients into a face buffer (3 corners × 2 per face); a per-vertex pass
// gathers its corners through the CSR vertex → (3·face + corner) list. No
// atomics, and the sum per vertex runs in a fixed order, so a backend gives
// the same result on every run.
// Step bound: per face, the first root of det(A(uv + t d)) = 0, then a min.
#pragma once

#include <memory>
#include <string>

#include "mesh/tri_mesh.h"
#include "param/planar/isometric_energy.h"

namespace paramorph::planar {

class IsometricKernels {
 public:
  virtual ~IsometricKernels() = default;

  /// Backend name ("cpu" or "opencl") and device description.
  virtual std::string backend() const = 0;
  virtual std::string device() const = 0;

  /// Σ area_f η_f for uv (#V by 2), +inf when a face has det <= 0. When
  /// `gradient` is given and the energy is finite it receives dE/duv (#V by 2).
  virtual double energy(const MatrixX2d& uv, MatrixX2d* gradient) = 0;

  /// Largest t such that no face of uv + s d inverts for s in [0, t); +inf
  /// when none ever does. uv must be fold-free.
  virtual double max_feasible_step(const MatrixX2d& uv, const MatrixX2d& d) = 0;
};

/// Both keep references to `mesh` and `factors`, which must outlive them.
std::unique_ptr<IsometricKernels> make_cpu_isometric_kernels(const TriMesh& mesh,
                                                             const IsometricFactors& factors);

/// nullptr with `why` filled when no OpenCL device is usable or the kernels do not build.
std::unique_ptr<IsometricKernels> make_opencl_isometric_kernels(const TriMesh& mesh,
                                                                const IsometricFactors& factors,
                                                                std::string& why);

}  // namespace paramorph::planar
