#include "param/spherical/relax_sphere_map.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <Eigen/Geometry>

#include "mesh/tri_mesh.h"
#include "param/spherical/isometric_sphere_map.h"

namespace paramorph::spherical {

RelaxPoorResult relax_poor_regions(const MatrixX3d& V, const MatrixX3i& F, MatrixX3d& X,
                                   const std::vector<char>& fixed, const RelaxPoorOptions& o) {
  RelaxPoorResult result;
  const IsometricSphereRest rest = isometric_sphere_rest(V, F);
  const VectorXd ratio = isometric_face_ratios(rest, F, X);
  // Area-weighted median of the ratios: the map's usual.
  std::vector<Index> order(std::size_t(F.rows()));
  std::iota(order.begin(), order.end(), Index(0));
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return ratio[a] < ratio[b]; });
  double half = 0.5 * rest.area.sum(), median = 1;
  for (const Index f : order)
    if ((half -= rest.area[f]) <= 0) {
      median = ratio[f];
      break;
    }
  std::vector<Index> poor;
  for (Index f = 0; f < F.rows(); ++f)
    if (ratio[f] > o.threshold * median) poor.push_back(f), result.worst_before = std::max(result.worst_before, ratio[f]);
  result.poor_faces = Index(poor.size());
  if (poor.empty()) return result;

  // The region: the poor faces and `rings` rings of faces round them.
  const TriMesh mesh(V, F);
  const Csr& corners = mesh.vertex_corners();
  std::vector<char> in(std::size_t(F.rows()), 0);
  std::vector<Index> front = poor;
  for (const Index f : poor) in[std::size_t(f)] = 1;
  for (int r = 0; r < o.rings; ++r) {
    std::vector<Index> next;
    for (const Index f : front)
      for (int k = 0; k < 3; ++k)
        for (Index c = corners.begin(F(f, k)); c < corners.end(F(f, k)); ++c) {
          const Index g = corners.items[c] / 3;
          if (!in[std::size_t(g)]) in[std::size_t(g)] = 1, next.push_back(g);
        }
    front.swap(next);
  }
  // Local numbering; a vertex with a face outside the region is its rim.
  std::unordered_map<Index, Index> local;
  std::vector<Index> global;
  std::vector<Index> faces;
  for (Index f = 0; f < F.rows(); ++f)
    if (in[std::size_t(f)]) faces.push_back(f);
  // A face flat or turned to rounding (a caller's fold test may allow a
  // triple product of -1e-13) has no finite energy to descend from: leave
  // the map as it is rather than fail.
  for (const Index f : faces)
    if (!std::isfinite(ratio[f])) {
      result.skipped = true;
      return result;
    }
  MatrixX3i RF(Index(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const auto [at, inserted] = local.emplace(F(faces[i], k), Index(global.size()));
      if (inserted) global.push_back(F(faces[i], k));
      RF(Index(i), k) = at->second;
    }
  MatrixX3d RV(Index(global.size()), 3), RX(Index(global.size()), 3);
  IsometricSphereOptions iso;
  iso.max_steps = o.max_steps;
  // The whole model's scale (the region's own would blow it up to the sphere).
  double model_area = 0;
  for (Index f = 0; f < F.rows(); ++f)
    model_area += 0.5 * (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0))).norm();
  iso.area_scale = 4 * M_PI / model_area;
  for (std::size_t i = 0; i < global.size(); ++i) {
    const Index v = global[i];
    RV.row(Index(i)) = V.row(v);
    RX.row(Index(i)) = X.row(v);
    bool rim = !fixed.empty() && fixed[std::size_t(v)];
    for (Index c = corners.begin(v); c < corners.end(v) && !rim; ++c) rim = !in[std::size_t(corners.items[c] / 3)];
    if (rim) iso.fixed.push_back(Index(i));
  }
  const IsometricSphereResult relaxed = isometric_sphere_map(RV, RF, RX, iso);
  result.region_faces = RF.rows();
  result.steps = relaxed.steps;
  for (std::size_t i = 0; i < global.size(); ++i) X.row(global[i]) = relaxed.positions.row(Index(i));
  const VectorXd after = isometric_face_ratios(rest, F, X);
  for (const Index f : poor) result.worst_after = std::max(result.worst_after, after[f]);
  return result;
}

}  // namespace paramorph::spherical
