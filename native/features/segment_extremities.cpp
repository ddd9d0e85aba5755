#include "features/segment_extremities.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/errors.h"
#include "features/merge_regions.h"
#include "features/peak_regions.h"
#include "mesh/validate.h"
#include "param/spherical/sphere_map.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::features {

Segmentation grow_stretch_regions(const TriMesh& mesh, const VectorXd& stretch, double threshold,
                                  double min_area) {
  const Index n = mesh.num_vertices();
  PM_REQUIRE(Index(stretch.size()) == n, InvalidInputError, "one stretch value per vertex expected");
  PM_REQUIRE(std::isfinite(min_area) && min_area >= 0 && min_area < 1, InvalidInputError,
             "min_area is a share of the surface in [0, 1), got ", min_area);
  VectorXd level(n);
  for (Index v = 0; v < n; ++v) {
    PM_REQUIRE(stretch[v] > 0 && std::isfinite(stretch[v]), InvalidInputError,
               "area stretch must be positive and finite (vertex ", v, " has ", stretch[v],
               "): is the sphere map folded?");
    level[v] = std::log(stretch[v]);
  }
  // The body's level: the weighted median of log A over the sphere (weights
  // surface area / A), where the squeezed extremities weigh almost nothing.
  const MatrixX3i& F = mesh.F();
  const VectorXd face_area = spherical::face_areas(mesh.V(), F);
  VectorXd sphere_weight = VectorXd::Zero(n);
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) sphere_weight[F(f, k)] += face_area[f] / 3.0;
  sphere_weight = sphere_weight.cwiseQuotient(stretch);
  std::vector<Index> order(n);
  std::iota(order.begin(), order.end(), Index(0));
  std::sort(order.begin(), order.end(),
            [&](Index a, Index b) { return level[a] != level[b] ? level[a] > level[b] : a < b; });
  double body_level = level[order.back()];
  const double half = 0.5 * sphere_weight.sum();
  double above = 0;
  for (Index v : order)
    if ((above += sphere_weight[v]) >= half) {
      body_level = level[v];
      break;
    }
  Segmentation s = peak_regions(mesh, level, body_level, threshold);
  if (min_area > 0 && s.regions() > 1) {
    Eigen::MatrixXd face_level(mesh.num_faces(), 1);
    for (Index f = 0; f < mesh.num_faces(); ++f)
      face_level(f, 0) = (level[F(f, 0)] + level[F(f, 1)] + level[F(f, 2)]) / 3.0;
    merge_small_regions(mesh, s, region_means(mesh, s, face_level), min_area * s.area.sum());
  }
  return s;
}

Segmentation segment_extremities(const MatrixX3d& V, const MatrixX3i& F,
                                 const ExtremityOptions& o, Progress* progress) {
  validate_arrays(V, F);
  MatrixX3d sphere;
  if (o.sphere) {
    sphere = *o.sphere;
    PM_REQUIRE(sphere.rows() == V.rows() && sphere.allFinite(), InvalidInputError,
               "sphere must be a finite (", V.rows(), ", 3) array, one point per vertex");
  } else {
    // sphere_map validates (closed, genus 0, ...) and raises the MeshError.
    spherical::SphereMapOptions conformal;
    conformal.keep_squeezed_start = true;  // its thresholds were measured on that map
    sphere = spherical::sphere_map(V, F, conformal, progress).positions;
  }
  const TriMesh mesh(V, F);
  return grow_stretch_regions(mesh, spherical::area_stretch(mesh, sphere), o.threshold,
                              o.min_area);
}

}  // namespace paramorph::features
