// Sampled one-sided and Hausdorff distances between surfaces (mesh/surface_distance.h).
#include "mesh/surface_distance.h"

#include "mesh/closest_points.h"

namespace paramorph {

namespace {

/// Vertices, edge midpoints (each edge once per face: a few twice) and face centroids.
MatrixX3d samples(const MatrixX3d& V, const MatrixX3i& F) {
  MatrixX3d out(V.rows() + 4 * F.rows(), 3);
  out.topRows(V.rows()) = V;
  Index k = Index(V.rows());
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    out.row(k++) = (a + b + c) / 3.0;
    out.row(k++) = 0.5 * (a + b);
    out.row(k++) = 0.5 * (b + c);
    out.row(k++) = 0.5 * (c + a);
  }
  return out;
}

void one_side(const MatrixX3d& V, const MatrixX3i& F, const ClosestPointTree& other, double* largest, double* mean) {
  const ClosestPoints found = other.query(samples(V, F));
  *largest = found.distance.size() ? found.distance.maxCoeff() : 0.0;
  *mean = found.distance.size() ? found.distance.mean() : 0.0;
}

}  // namespace

SurfaceDistance surface_distance(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB) {
  SurfaceDistance out;
  const ClosestPointTree tree_a(VA, FA), tree_b(VB, FB);
  one_side(VA, FA, tree_b, &out.a_to_b, &out.mean_a_to_b);
  one_side(VB, FB, tree_a, &out.b_to_a, &out.mean_b_to_a);
  return out;
}

}  // namespace paramorph
