// Walking point location on a sphere map (morph/point_location.h).
#include "morph/point_location.h"

#include <cstdint>

#include <Eigen/Geometry>

#include "mesh/face_neighbors.h"
#include "mesh/tri_mesh.h"
#include "mesh/closest_points.h"

namespace paramorph::morph {

namespace {

/// Side of p seen from the edge opposite corner k of face f: > 0 inside.
int side(const MatrixX3d& X, const MatrixX3i& F, bool ranked, Index f, int k,
         const SpherePoint& p) {
  const Index u = F(f, (k + 1) % 3), v = F(f, (k + 2) % 3);
  return perturbed_orientation({X.row(u).data(), ranked ? u : -1},
                               {X.row(v).data(), ranked ? v : -1}, p);
}

bool holds(const MatrixX3d& X, const MatrixX3i& F, bool ranked, Index f, const SpherePoint& p) {
  for (int k = 0; k < 3; ++k)
    if (side(X, F, ranked, f, k, p) < 0) return false;
  return true;
}

}  // namespace

Index locate_on_sphere(const MatrixX3d& X, const MatrixX3i& F, const MatrixX3i& neighbors,
                       bool ranked_vertices, const SpherePoint& p, Index start_face) {
  const Index faces = Index(F.rows());
  if (faces == 0) return -1;
  Index f = start_face >= 0 && start_face < faces ? start_face : 0;
  std::uint32_t state = 0x9e3779b9u;  // xorshift: which separating edge to try first
  const Index max_steps = 2 * faces + 64;
  for (Index step = 0; step < max_steps; ++step) {
    state ^= state << 13, state ^= state >> 17, state ^= state << 5;
    const int first = int(state % 3);
    int k = -1;
    for (int t = 0; t < 3 && k < 0; ++t)
      if (side(X, F, ranked_vertices, f, (first + t) % 3, p) < 0) k = (first + t) % 3;
    if (k < 0) return f;             // no edge separates p from f
    if (neighbors(f, k) < 0) break;  // an open map: test every face instead
    f = neighbors(f, k);
  }
  for (Index g = 0; g < faces; ++g)
    if (holds(X, F, ranked_vertices, g, p)) return g;
  return -1;
}

SphereLocations locate_on_sphere_map(const MatrixX3d& X, const MatrixX3i& F, const MatrixX3d& points) {
  const MatrixX3i neighbors = face_neighbors(TriMesh(X, F));
  const ClosestPoints nearest = ClosestPointTree(X, F).query(points.rowwise().normalized());
  SphereLocations out;
  out.face.resize(points.rows());
  out.bary.resize(points.rows(), 3);
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < points.rows(); ++i) {
    const Eigen::RowVector3d p = points.row(i);
    // The walk fails only on a map that folds (a caller's input): the
    // nearest face is then the best answer there is, never an index of -1.
    const Index walked = locate_on_sphere(X, F, neighbors, false, {p.data(), -1}, nearest.face[i]);
    const Index f = walked >= 0 ? walked : nearest.face[i];
    out.face[i] = f;
    const Eigen::RowVector3d a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
    Eigen::RowVector3d w(p.dot(b.cross(c)), p.dot(c.cross(a)), p.dot(a.cross(b)));
    w = w.cwiseMax(0.0);
    out.bary.row(i) = w.sum() > 0 ? (w / w.sum()).eval() : Eigen::RowVector3d(1, 0, 0);
  }
  return out;
}

}  // namespace paramorph::morph
