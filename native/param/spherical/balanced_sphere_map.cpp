#include "param/spherical/balanced_sphere_map.h"

#include <algorithm>
#include <cmath>

#include "common/errors.h"
#include "mesh/validate.h"

namespace paramorph::spherical {

BalancedSphereResult balanced_sphere_map(const MatrixX3d& V, const MatrixX3i& F, const BalancedSphereOptions& o,
                                         Progress* progress) {
  validate_arrays(V, F);
  const TriMesh mesh(V, F);
  require_closed_genus0(validate(mesh));
  PM_REQUIRE(std::isfinite(o.polish_face_steps) && o.polish_face_steps >= 0, InvalidInputError,
             "polish_face_steps must be a number >= 0");
  BalancedSphereResult result;
  const ProgressiveSphereResult start = progressive_sphere_map(mesh, o.progressive, ProgressWindow(progress, 0.0, 0.5));
  result.levels = start.levels;
  IsometricSphereOptions polish = o.isometric;
  polish.max_steps = int(std::min<double>(polish.max_steps, std::ceil(o.polish_face_steps / double(F.rows()))));
  const IsometricSphereResult relaxed =
      isometric_sphere_map(V, F, start.positions, polish, ProgressWindow(progress, 0.5, 1.0));
  result.positions = relaxed.positions;
  result.steps = relaxed.steps;
  result.start_energy = relaxed.start_energy;
  result.energy = relaxed.energy;
  if (progress) progress->report(1.0, "balanced sphere map");
  return result;
}

}  // namespace paramorph::spherical
