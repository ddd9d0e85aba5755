#include "features/merge_regions.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <queue>
#include <set>

#include "common/errors.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::features {

Eigen::MatrixXd region_means(const TriMesh& mesh, const Segmentation& s,
                             const Eigen::MatrixXd& face_values) {
  PM_REQUIRE(face_values.rows() == mesh.num_faces(), InvalidInputError,
             "one row of values per face expected, got ", face_values.rows());
  const VectorXd face_area = spherical::face_areas(mesh.V(), mesh.F());
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(s.regions(), face_values.cols());
  VectorXd area = VectorXd::Zero(s.regions());
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    sum.row(s.face_labels[f]) += face_area[f] * face_values.row(f);
    area[s.face_labels[f]] += face_area[f];
  }
  for (Index r = 0; r < s.regions(); ++r)
    if (area[r] > 0) sum.row(r) /= area[r];
  return sum;
}

void merge_small_regions(const TriMesh& mesh, Segmentation& s, Eigen::MatrixXd descriptor,
                         double min_area) {
  const Index regions = s.regions();
  PM_REQUIRE(descriptor.rows() == regions, InvalidInputError,
             "one descriptor row per region expected");
  PM_REQUIRE(descriptor.allFinite(), InvalidInputError, "region descriptors must be finite");
  if (s.area.size() != regions) summarise_regions(mesh, s);
  VectorXd area = s.area;
  std::vector<std::set<Index>> neighbours(regions);
  for (const auto& [a, b] : s.adjacency) neighbours[a].insert(b), neighbours[b].insert(a);

  std::vector<Index> absorbed_by(regions);
  std::iota(absorbed_by.begin(), absorbed_by.end(), Index(0));
  using Item = std::pair<double, Index>;  // (area when queued, region)
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> smallest;
  for (Index r = 0; r < regions; ++r)
    if (area[r] < min_area) smallest.emplace(area[r], r);
  while (!smallest.empty()) {
    const auto [queued_area, r] = smallest.top();
    smallest.pop();
    if (absorbed_by[r] != r || queued_area != area[r] || neighbours[r].empty()) continue;
    Index into = -1;
    double nearest = std::numeric_limits<double>::infinity();
    for (Index n : neighbours[r]) {
      const double d = (descriptor.row(n) - descriptor.row(r)).squaredNorm();
      // Ties (equal descriptors) go to the larger neighbour, then the lower index.
      if (d < nearest || (d == nearest && area[n] > area[into])) nearest = d, into = n;
    }
    descriptor.row(into) =
        (area[into] * descriptor.row(into) + area[r] * descriptor.row(r)) / (area[into] + area[r]);
    area[into] += area[r];
    absorbed_by[r] = into;
    for (Index n : neighbours[r]) {
      neighbours[n].erase(r);
      if (n != into) neighbours[n].insert(into), neighbours[into].insert(n);
    }
    neighbours[r].clear();
    if (area[into] < min_area) smallest.emplace(area[into], into);
  }

  // Follow each chain of absorptions to the region that survived.
  std::vector<Index> survivor(regions), renumber(regions, -1);
  std::vector<Index> seeds;
  for (Index r = 0; r < regions; ++r) {
    Index root = r;
    while (absorbed_by[root] != root) root = absorbed_by[root];
    survivor[r] = root;
  }
  for (Index r = 0; r < regions; ++r)
    if (survivor[r] == r) renumber[r] = Index(seeds.size()), seeds.push_back(s.seeds[r]);
  for (Index f = 0; f < mesh.num_faces(); ++f)
    s.face_labels[f] = renumber[survivor[s.face_labels[f]]];
  s.seeds = std::move(seeds);
  summarise_regions(mesh, s);
}

}  // namespace paramorph::features
