#include "features/segment_extremities.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/errors.h"
#include "features/merge_regions.h"
#include "mesh/validate.h"
#include "param/spherical/sphere_map.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::features {

namespace {

/// Union-find with path halving; the root of a set is its representative.
struct DisjointSets {
  std::vector<Index> parent;
  explicit DisjointSets(Index n) : parent(n) { std::iota(parent.begin(), parent.end(), Index(0)); }
  Index find(Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
};

/// Faces take the label most of their corners have; with three different
/// labels, the one whose seed is closest in stretch to its corner.
VectorXi label_faces(const TriMesh& mesh, const std::vector<Index>& vertex_region,
                     const VectorXd& value, const std::vector<Index>& seeds) {
  const MatrixX3i& F = mesh.F();
  VectorXi face_label(mesh.num_faces());
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index a = vertex_region[F(f, 0)], b = vertex_region[F(f, 1)], c = vertex_region[F(f, 2)];
    if (a == b || a == c) {
      face_label[f] = a;
    } else if (b == c) {
      face_label[f] = b;
    } else {
      int best = 0;
      double closest = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k) {
        const Index v = F(f, k);
        const double d = std::abs(value[v] - value[seeds[vertex_region[v]]]);
        if (d < closest) closest = d, best = k;
      }
      face_label[f] = vertex_region[F(f, best)];
    }
  }
  return face_label;
}

}  // namespace

Segmentation grow_stretch_regions(const TriMesh& mesh, const VectorXd& stretch, double threshold,
                                  double min_area) {
  const Index n = mesh.num_vertices();
  PM_REQUIRE(Index(stretch.size()) == n, InvalidInputError, "one stretch value per vertex expected");
  PM_REQUIRE(std::isfinite(threshold) && threshold > 0, InvalidInputError,
             "threshold must be a positive number, got ", threshold);
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
  double above = 0;
  for (Index v : order)
    if ((above += sphere_weight[v]) >= 0.5 * sphere_weight.sum()) {
      body_level = level[v];
      break;
    }
  const auto extremity_end =
      std::find_if(order.begin(), order.end(), [&](Index v) { return level[v] <= body_level + threshold; });

  // Extremities: the vertices `threshold` above the body, swept from the
  // top. Components of the vertices swept so far (the part above the current
  // level) keep their highest level and the region still growing in them;
  // regions absorbed into another are followed through `merged_into`.
  const Csr& ring = mesh.vertex_neighbors();
  DisjointSets component(n), merged_into(0);
  std::vector<double> peak(n), region_top;
  std::vector<Index> growing(n, -1), vertex_region(n, -1), region_seed;
  auto new_region = [&](Index seed) {
    region_seed.push_back(seed);
    region_top.push_back(level[seed]);
    merged_into.parent.push_back(Index(merged_into.parent.size()));
    return Index(region_seed.size()) - 1;
  };
  std::vector<Index> met;
  for (auto it = order.begin(); it != extremity_end; ++it) {
    const Index v = *it;
    met.clear();
    for (Index k = ring.begin(v); k < ring.end(v); ++k)
      if (vertex_region[ring.items[k]] >= 0) met.push_back(component.find(ring.items[k]));
    std::sort(met.begin(), met.end());
    met.erase(std::unique(met.begin(), met.end()), met.end());

    if (met.empty()) {  // a seed candidate: a local maximum (Def. 3.2)
      peak[v] = level[v];
      growing[v] = vertex_region[v] = new_region(v);
      continue;
    }
    Index region = growing[met[0]];
    if (met.size() > 1) {
      // Components whose peak rose `threshold` above here are features; the
      // rest are bumps. A feature's region stops here if it spans the
      // threshold itself; everything else continues as one region.
      int features = 0;
      for (Index c : met) features += peak[c] - level[v] >= threshold;
      std::vector<Index> continuing;
      for (Index c : met) {
        const bool feature = peak[c] - level[v] >= threshold;
        const bool complete = region_top[growing[c]] - level[v] >= threshold;
        if (features < 2 || !feature || !complete) continuing.push_back(growing[c]);
      }
      if (continuing.empty()) {
        region = new_region(v);
      } else {
        region = *std::max_element(continuing.begin(), continuing.end(), [&](Index a, Index b) {
          return region_top[a] < region_top[b];
        });
        for (Index r : continuing) merged_into.parent[merged_into.find(r)] = merged_into.find(region);
      }
    }
    Index root = met[0];
    for (Index c : met) {
      peak[root] = std::max(peak[root], peak[c]);
      component.parent[c] = root;
    }
    component.parent[v] = root;
    growing[root] = vertex_region[v] = region;
  }

  // The body: each connected part of the rest, grown from its lowest vertex
  // (a local minimum, Def. 3.2).
  std::vector<Index> stack;
  for (auto it = order.rbegin(); it.base() != extremity_end; ++it) {
    if (vertex_region[*it] >= 0) continue;
    const Index region = new_region(*it);
    vertex_region[*it] = region;
    stack.assign(1, *it);
    while (!stack.empty()) {
      const Index v = stack.back();
      stack.pop_back();
      for (Index k = ring.begin(v); k < ring.end(v); ++k) {
        const Index u = ring.items[k];
        if (vertex_region[u] < 0 && level[u] <= body_level + threshold)
          vertex_region[u] = region, stack.push_back(u);
      }
    }
  }

  // Regions by the survivor of their merges, numbered in order of their seeds.
  const Index regions = Index(region_seed.size());
  std::vector<Index> number(regions, -1);
  std::vector<Index> seeds;
  for (Index r = 0; r < regions; ++r)
    if (merged_into.find(r) == r) number[r] = Index(seeds.size()), seeds.push_back(region_seed[r]);
  for (Index v = 0; v < n; ++v) vertex_region[v] = number[merged_into.find(vertex_region[v])];

  Segmentation s;
  s.face_labels = label_faces(mesh, vertex_region, level, seeds);
  // Regions that kept no face (a lone vertex outvoted on all its faces) go.
  std::vector<Index> kept(seeds.size(), -1);
  for (Index f = 0; f < mesh.num_faces(); ++f) kept[s.face_labels[f]] = 0;
  for (std::size_t r = 0; r < seeds.size(); ++r)
    if (kept[r] == 0) kept[r] = Index(s.seeds.size()), s.seeds.push_back(seeds[r]);
  for (Index f = 0; f < mesh.num_faces(); ++f) s.face_labels[f] = kept[s.face_labels[f]];
  summarise_regions(mesh, s);

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
    sphere = spherical::sphere_map(V, F, {}, progress).positions;
  }
  const TriMesh mesh(V, F);
  return grow_stretch_regions(mesh, spherical::area_stretch(mesh, sphere), o.threshold,
                              o.min_area);
}

}  // namespace paramorph::features
