#include "param/spherical/smooth_sphere_map.h"

#include <algorithm>
#include <limits>

#include <Eigen/Geometry>

namespace paramorph::spherical {

namespace {

double triple(const MatrixX3d& X, const MatrixX3i& F, Index f) {
  return X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2))));
}

}  // namespace

Index smooth_sphere_map(const TriMesh& mesh, MatrixX3d& X, const std::vector<Index>& vertices,
                        const std::vector<char>& fixed, int rounds) {
  const MatrixX3i& F = mesh.F();
  const Csr& ring = mesh.vertex_neighbors();
  const Csr& corners = mesh.vertex_corners();
  Index moved = 0;
  for (int round = 0; round < rounds; ++round)
    for (const Index v : vertices) {
      if (!fixed.empty() && fixed[std::size_t(v)]) continue;
      Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
      for (Index k = ring.begin(v); k < ring.end(v); ++k) centre += X.row(ring.items[k]);
      if (!(centre.norm() > 0)) continue;
      centre.normalize();
      auto thinnest = [&] {
        double lowest = std::numeric_limits<double>::infinity();
        for (Index c = corners.begin(v); c < corners.end(v); ++c) lowest = std::min(lowest, triple(X, F, corners.items[c] / 3));
        return lowest;
      };
      const double before = thinnest();
      const Eigen::RowVector3d here = X.row(v);
      for (double t = 1.0; t > 1.0 / 64; t *= 0.5) {
        X.row(v) = ((1 - t) * here + t * centre).normalized();
        const double after = thinnest();
        if (after > 0 && after >= before) {  // the thinnest face of the vertex is no thinner
          ++moved;
          break;
        }
        X.row(v) = here;
      }
    }
  return moved;
}

std::vector<Index> vertices_near_faces(const TriMesh& mesh, const std::vector<Index>& faces, int rings) {
  const MatrixX3i& F = mesh.F();
  const Csr& ring = mesh.vertex_neighbors();
  std::vector<char> in(std::size_t(mesh.num_vertices()), 0);
  std::vector<Index> out;
  for (const Index f : faces)
    for (int k = 0; k < 3; ++k)
      if (!in[std::size_t(F(f, k))]) in[std::size_t(F(f, k))] = 1, out.push_back(F(f, k));
  std::size_t begin = 0;
  for (int r = 0; r < rings; ++r) {
    const std::size_t end = out.size();
    for (std::size_t i = begin; i < end; ++i)
      for (Index k = ring.begin(out[i]); k < ring.end(out[i]); ++k) {
        const Index u = ring.items[k];
        if (!in[std::size_t(u)]) in[std::size_t(u)] = 1, out.push_back(u);
      }
    begin = end;
  }
  return out;
}

}  // namespace paramorph::spherical
