#include "features/feature_points.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "common/errors.h"
#include "mesh/validate.h"

namespace paramorph::features {

namespace {

/// The region most of a vertex's faces belong to (ties: the lowest label).
Index majority_region(const TriMesh& mesh, const VectorXi& face_labels, Index v) {
  const Csr& corners = mesh.vertex_corners();
  std::map<Index, int> count;
  for (Index k = corners.begin(v); k < corners.end(v); ++k) ++count[face_labels[corners.items[k] / 3]];
  return std::max_element(count.begin(), count.end(), [](const auto& a, const auto& b) {
           return a.second < b.second;
         })->first;
}

}  // namespace

FeaturePoints feature_points(const MatrixX3d& V, const MatrixX3i& F, const VectorXi& face_labels,
                             const VectorXd& concavity, const FeaturePointOptions& o) {
  validate_arrays(V, F);
  PM_REQUIRE(face_labels.size() == F.rows(), InvalidInputError, "one label per face expected, got ",
             face_labels.size(), " for ", F.rows(), " faces");
  PM_REQUIRE(face_labels.size() == 0 || face_labels.minCoeff() >= 0, InvalidInputError,
             "face labels must be >= 0");
  PM_REQUIRE(concavity.size() == V.rows() && concavity.allFinite(), InvalidInputError,
             "concavity must be one finite value per vertex");
  PM_REQUIRE(std::isfinite(o.spacing) && o.spacing >= 0, InvalidInputError,
             "spacing must be >= 0, got ", o.spacing);
  const TriMesh mesh(V, F);
  const Index n = mesh.num_vertices();
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  const double on_hull = 1e-9 * diagonal;
  const Eigen::RowVector3d centroid = V.colwise().mean();
  const VectorXd reach = (V.rowwise() - centroid).rowwise().norm();

  // Strict extrema with ties to the lower index: (value, -index) comparisons.
  auto above = [](double a, Index ia, double b, Index ib) { return a > b || (a == b && ia < ib); };
  const Csr& ring = mesh.vertex_neighbors();
  struct Candidate {
    Index vertex, region;
    int kind;
    double strength;
  };
  std::vector<Candidate> candidates;
  for (Index v = 0; v < n; ++v) {
    if (ring.size(v) == 0) continue;
    const bool hull = concavity[v] <= on_hull;
    bool extreme = true;
    for (Index k = ring.begin(v); k < ring.end(v) && extreme; ++k) {
      const Index u = ring.items[k];
      if (hull)
        extreme = concavity[u] > on_hull || above(reach[v], v, reach[u], u);
      else
        extreme = above(concavity[v], v, concavity[u], u);
    }
    if (extreme)
      candidates.push_back({v, majority_region(mesh, face_labels, v), hull ? -1 : +1,
                            hull ? reach[v] : concavity[v]});
  }
  // Most extreme first within each (region, kind); then spaced out.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    if (a.region != b.region) return a.region < b.region;
    if (a.kind != b.kind) return a.kind > b.kind;
    return a.strength != b.strength ? a.strength > b.strength : a.vertex < b.vertex;
  });
  const double min_distance = o.spacing * diagonal;
  FeaturePoints out;
  std::size_t group_start = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Candidate& c = candidates[i];
    if (i > 0 && (c.region != candidates[i - 1].region || c.kind != candidates[i - 1].kind))
      group_start = out.vertices.size();
    bool spaced = true;
    for (std::size_t j = group_start; j < out.vertices.size() && spaced; ++j)
      spaced = (V.row(out.vertices[j]) - V.row(c.vertex)).norm() >= min_distance;
    if (!spaced) continue;
    out.vertices.push_back(c.vertex);
    out.regions.push_back(c.region);
    out.kinds.push_back(c.kind);
  }
  return out;
}

}  // namespace paramorph::features
