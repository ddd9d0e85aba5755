#include "features/feature_regions.h"

#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "features/concavity.h"
#include "features/merge_regions.h"
#include "features/peak_regions.h"
#include "mesh/validate.h"

namespace paramorph::features {

namespace {

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

/// Splits the regions of `s` across edges whose faces' normals differ by
/// more than the angle whose cosine is `min_cos`; each piece keeps its
/// region's seed if it holds it, else takes its deepest vertex.
Segmentation split_at_creases(const TriMesh& mesh, const Segmentation& s,
                              const Eigen::MatrixXd& normals, double min_cos,
                              const VectorXd& level) {
  const MatrixX3i& F = mesh.F();
  const MatrixX3i& face_edges = mesh.face_edges();
  const Csr& edge_faces = mesh.edge_faces();
  Segmentation out;
  out.face_labels = VectorXi::Constant(mesh.num_faces(), -1);
  std::vector<bool> seed_taken(s.seeds.size(), false);
  std::vector<Index> stack;
  for (Index start = 0; start < mesh.num_faces(); ++start) {
    if (out.face_labels[start] >= 0) continue;
    const Index label = s.face_labels[start], piece = out.regions();
    Index deepest = F(start, 0);
    bool holds_seed = false;
    out.face_labels[start] = piece;
    stack.assign(1, start);
    while (!stack.empty()) {
      const Index f = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const Index v = F(f, k);
        holds_seed = holds_seed || v == s.seeds[label];
        if (level[v] > level[deepest]) deepest = v;
        const Index e = face_edges(f, k);
        for (Index i = edge_faces.begin(e); i < edge_faces.end(e); ++i) {
          const Index g = edge_faces.items[i];
          if (out.face_labels[g] < 0 && s.face_labels[g] == label &&
              normals.row(f).dot(normals.row(g)) >= min_cos)
            out.face_labels[g] = piece, stack.push_back(g);
        }
      }
    }
    const bool keeps_seed = holds_seed && !seed_taken[label];
    if (keeps_seed) seed_taken[label] = true;
    out.seeds.push_back(keeps_seed ? s.seeds[label] : deepest);
  }
  summarise_regions(mesh, out);
  return out;
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

  const Segmentation pockets = peak_regions(mesh, depth, 0.0, o.concavity_threshold);
  const Eigen::MatrixXd normals = unit_face_normals(mesh);
  const double radians = o.normal_angle * M_PI / 180.0;
  Segmentation s = split_at_creases(mesh, pockets, normals, std::cos(radians), depth);

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
