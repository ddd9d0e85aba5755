#include "features/segment_extremities.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

#include "common/errors.h"
#include "mesh/validate.h"
#include "param/spherical/sphere_map.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::features {

namespace {

/// Vertices whose value is >= or <= all their neighbours' (Def. 3.2).
std::vector<Index> local_extrema(const TriMesh& mesh, const VectorXd& value) {
  const Csr& ring = mesh.vertex_neighbors();
  std::vector<Index> out;
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    bool is_max = true, is_min = true;
    for (Index k = ring.begin(v); k < ring.end(v); ++k) {
      is_max = is_max && value[v] >= value[ring.items[k]];
      is_min = is_min && value[v] <= value[ring.items[k]];
    }
    if ((is_max || is_min) && ring.size(v) > 0) out.push_back(v);
  }
  return out;
}

}  // namespace

Segmentation grow_stretch_regions(const TriMesh& mesh, const VectorXd& stretch, double threshold) {
  const Index n = mesh.num_vertices();
  PM_REQUIRE(Index(stretch.size()) == n, InvalidInputError, "one stretch value per vertex expected");
  PM_REQUIRE(std::isfinite(threshold) && threshold > 0, InvalidInputError,
             "threshold must be a positive number, got ", threshold);
  VectorXd log_stretch(n);
  for (Index v = 0; v < n; ++v) {
    PM_REQUIRE(stretch[v] > 0 && std::isfinite(stretch[v]), InvalidInputError,
               "area stretch must be positive and finite (vertex ", v, " has ", stretch[v],
               "): is the sphere map folded?");
    log_stretch[v] = std::log(stretch[v]);
  }
  auto descending = [&](Index a, Index b) {
    return log_stretch[a] != log_stretch[b] ? log_stretch[a] > log_stretch[b] : a < b;
  };
  std::vector<Index> order = local_extrema(mesh, log_stretch);
  std::sort(order.begin(), order.end(), descending);
  std::vector<Index> rest(n);
  std::iota(rest.begin(), rest.end(), Index(0));
  std::sort(rest.begin(), rest.end(), descending);
  order.insert(order.end(), rest.begin(), rest.end());

  const Csr& ring = mesh.vertex_neighbors();
  std::vector<Index> label(n, -1);
  std::vector<Index> seeds;
  using Item = std::pair<double, Index>;  // (variation from the seed, vertex)
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> frontier;
  for (Index seed : order) {
    if (label[seed] >= 0) continue;
    const Index region = Index(seeds.size());
    seeds.push_back(seed);
    frontier.emplace(0.0, seed);
    while (!frontier.empty()) {
      const auto [variation, v] = frontier.top();
      frontier.pop();
      if (label[v] >= 0) continue;
      label[v] = region;
      for (Index k = ring.begin(v); k < ring.end(v); ++k) {
        const Index u = ring.items[k];
        const double d = std::abs(log_stretch[u] - log_stretch[seed]);
        if (label[u] < 0 && d <= threshold) frontier.emplace(d, u);
      }
    }
  }

  // Faces: the label most corners have; three different ones: the corner
  // closest in stretch to its own seed.
  const MatrixX3i& F = mesh.F();
  VectorXi face_label(mesh.num_faces());
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index a = label[F(f, 0)], b = label[F(f, 1)], c = label[F(f, 2)];
    if (a == b || a == c) {
      face_label[f] = int(a);
    } else if (b == c) {
      face_label[f] = int(b);
    } else {
      int best = 0;
      double closest = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k) {
        const Index v = F(f, k);
        const double d = std::abs(log_stretch[v] - log_stretch[seeds[label[v]]]);
        if (d < closest) closest = d, best = k;
      }
      face_label[f] = int(label[F(f, best)]);
    }
  }
  // Regions that kept no face (a lone vertex outvoted on all its faces) go.
  std::vector<Index> renumber(seeds.size(), -1);
  for (Index f = 0; f < mesh.num_faces(); ++f) renumber[face_label[f]] = 0;
  Segmentation s;
  for (std::size_t r = 0; r < seeds.size(); ++r)
    if (renumber[r] == 0) renumber[r] = Index(s.seeds.size()), s.seeds.push_back(seeds[r]);
  s.face_labels.resize(mesh.num_faces());
  for (Index f = 0; f < mesh.num_faces(); ++f) s.face_labels[f] = int(renumber[face_label[f]]);
  summarise_regions(mesh, s);
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
    sphere = spherical::sphere_map(V, F, {}, progress).positions;
  }
  const TriMesh mesh(V, F);
  return grow_stretch_regions(mesh, spherical::area_stretch(mesh, sphere), o.threshold);
}

}  // namespace paramorph::features
