#include "features/feature_regions.h"

#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "features/concavity.h"
#include "features/merge_regions.h"
#include "features/peak_regions.h"
#include "mesh/validate.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::features {

namespace {

/// Faces within this angle (radians, about 1 degree) of a plane count as in it.
constexpr double kFlatTolerance = 0.0175;

Eigen::MatrixXd unit_face_normals(const TriMesh& mesh) {
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  Eigen::MatrixXd N(mesh.num_faces(), 3);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    N.row(f) = (b - a).cross(c - a).normalized().transpose();
  }
  return N;
}

/// Joins adjacent regions that lie in one plane: each flat (every face
/// normal within `tolerance` radians of the region's mean), the two means
/// within `tolerance` and their plane offsets within `distance`. The
/// concavity sweep may cut a flat side of a CAD part into pieces (its depth
/// below the hull varies across it); flat regions are never features apart.
void merge_coplanar_regions(const TriMesh& mesh, const Eigen::MatrixXd& normals, double tolerance,
                            double distance, Segmentation& s) {
  const Index regions = s.regions();
  const VectorXd face_area = spherical::face_areas(mesh.V(), mesh.F());
  Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(regions, 3);
  for (Index f = 0; f < mesh.num_faces(); ++f) mean.row(s.face_labels[f]) += face_area[f] * normals.row(f);
  mean.rowwise().normalize();
  const double min_cos = std::cos(tolerance);
  std::vector<bool> flat(regions, true);
  for (Index f = 0; f < mesh.num_faces(); ++f)
    if (normals.row(f).dot(mean.row(s.face_labels[f])) < min_cos) flat[s.face_labels[f]] = false;

  std::vector<Index> parent(regions);
  std::iota(parent.begin(), parent.end(), Index(0));
  auto find = [&](Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  bool merged = false;
  for (const auto& [a, b] : s.adjacency) {
    const double offset_a = mean.row(a).dot(s.centroid.row(a));
    const double offset_b = mean.row(a).dot(s.centroid.row(b));
    if (flat[a] && flat[b] && mean.row(a).dot(mean.row(b)) >= min_cos &&
        std::abs(offset_a - offset_b) <= distance) {
      const Index ra = find(a), rb = find(b);
      if (ra == rb) continue;
      // The larger region's seed stands for the union.
      if (s.area[ra] >= s.area[rb])
        parent[rb] = ra;
      else
        parent[ra] = rb;
      merged = true;
    }
  }
  if (!merged) return;
  std::vector<Index> number(regions, -1), seeds;
  for (Index r = 0; r < regions; ++r)
    if (find(r) == r) number[r] = Index(seeds.size()), seeds.push_back(s.seeds[r]);
  for (Index f = 0; f < mesh.num_faces(); ++f) s.face_labels[f] = number[find(s.face_labels[f])];
  s.seeds = std::move(seeds);
  summarise_regions(mesh, s);
}

}  // namespace

Segmentation grow_feature_regions(const TriMesh& mesh, const VectorXd& concavity,
                                  const FeatureRegionOptions& o) {
  PM_REQUIRE(std::isfinite(o.normal_angle) && o.normal_angle > 0 && o.normal_angle <= 180,
             InvalidInputError, "normal_angle must be in (0, 180] degrees, got ", o.normal_angle);
  PM_REQUIRE(std::isfinite(o.concavity_threshold) && o.concavity_threshold > 0, InvalidInputError,
             "concavity_threshold must be a positive share of the bounding-box diagonal, got ",
             o.concavity_threshold);
  PM_REQUIRE(std::isfinite(o.min_area) && o.min_area >= 0 && o.min_area < 1, InvalidInputError,
             "min_area is a share of the surface in [0, 1), got ", o.min_area);
  PM_REQUIRE(Index(concavity.size()) == mesh.num_vertices() && concavity.allFinite() &&
                 (concavity.size() == 0 || concavity.minCoeff() >= 0),
             InvalidInputError, "concavity must be one finite value >= 0 per vertex");
  const MatrixX3d& V = mesh.V();
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  const VectorXd depth = concavity / diagonal;  // scale-free

  Segmentation s = peak_regions(mesh, depth, 0.0, o.concavity_threshold);
  const Eigen::MatrixXd normals = unit_face_normals(mesh);
  const double radians = o.normal_angle * M_PI / 180.0, min_cos = std::cos(radians);
  split_regions(mesh, depth, s, [&](Index f, Index g) {  // not across creases
    return normals.row(f).dot(normals.row(g)) >= min_cos;
  });
  merge_coplanar_regions(mesh, normals, kFlatTolerance, 1e-4 * diagonal, s);

  if (o.min_area > 0 && s.regions() > 1) {
    // Similarity in units of the thresholds: a normal turned by normal_angle
    // weighs as much as a depth difference of concavity_threshold.
    const MatrixX3i& F = mesh.F();
    Eigen::MatrixXd face_descriptor(mesh.num_faces(), 4);
    face_descriptor.leftCols(3) = normals / (2.0 * std::sin(0.5 * radians));
    for (Index f = 0; f < mesh.num_faces(); ++f)
      face_descriptor(f, 3) =
          (depth[F(f, 0)] + depth[F(f, 1)] + depth[F(f, 2)]) / (3.0 * o.concavity_threshold);
    merge_small_regions(mesh, s, region_means(mesh, s, face_descriptor), o.min_area * s.area.sum());
  }
  return s;
}

Segmentation feature_regions(const MatrixX3d& V, const MatrixX3i& F,
                             const FeatureRegionOptions& o, Progress* progress) {
  validate_arrays(V, F);
  const TriMesh mesh(V, F);
  const MeshReport report = validate(mesh);
  PM_REQUIRE(report.degenerate_faces.empty(), DegenerateFaceError, "mesh has ",
             report.degenerate_faces.size(), " degenerate faces (",
             format_indices(report.degenerate_faces), "): they have no normal");
  PM_REQUIRE(report.non_manifold_edges.empty(), NonManifoldError,
             "mesh is not manifold: edges ", format_vertex_pairs(report.non_manifold_edge_vertices),
             " have more than two faces");
  if (progress) progress->report(0.0, "concavity");
  const VectorXd intensity = o.concavity ? *o.concavity : concavity(V, F);
  if (progress) progress->report(0.5, "feature regions");
  Segmentation s = grow_feature_regions(mesh, intensity, o);
  if (progress) progress->report(1.0, "feature regions");
  return s;
}

}  // namespace paramorph::features
