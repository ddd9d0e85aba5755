#include "morph/optimization_start.h"

#include "common/errors.h"
#include "morph/optimize_sphere_map.h"
#include "param/spherical/sphere_map.h"

namespace paramorph::morph {

MatrixX3d optimization_start(const MatrixX3d& V, const MatrixX3i& F, Progress* progress) {
  // The conformal map as the thesis computes it, squeezed limbs and all:
  // then the relaxed projection replaces it (see the header).
  spherical::SphereMapOptions squeezed;
  squeezed.keep_squeezed_start = true;
  MatrixX3d conformal = spherical::sphere_map(V, F, squeezed, progress).positions;
  const VectorXd det = face_triple_products(conformal.rowwise().normalized(), F);
  if (det.minCoeff() >= kSqueezedShare * det.mean()) return conformal;
  spherical::SphereMapOptions relaxation;
  relaxation.init = spherical::InitialMap::Relaxation;
  relaxation.max_outer_iterations = 0;
  try {
    return spherical::sphere_map(V, F, relaxation, progress).positions;
  } catch (const ComputeError&) {  // the projection still folds after the relaxation's sweeps
    return conformal;
  }
}

}  // namespace paramorph::morph
