// Sampled one-sided and Hausdorff distances between surfaces (mesh/surface_distance.h).
#include "mesh/surface_distance.h"

#include <algorithm>

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

/// The samples of (V, F) against `other`, in chunks with a report between
/// them (into [lo, hi] of `progress`).
void one_side(const MatrixX3d& V, const MatrixX3i& F, const ClosestPointTree& other, double* largest, double* mean,
              Progress* progress, double lo, double hi) {
  constexpr Index kChunk = 16384;  // ~0.1 s of queries between reports
  const MatrixX3d points = samples(V, F);
  const Index n = Index(points.rows());
  double most = 0.0, sum = 0.0;
  for (Index first = 0; first < n; first += kChunk) {
    if (progress) progress->report(lo + (hi - lo) * double(first) / double(n), "surface distance");
    const ClosestPoints found = other.query(points.middleRows(first, std::min(kChunk, n - first)));
    most = std::max(most, found.distance.maxCoeff());
    sum += found.distance.sum();
  }
  *largest = most;
  *mean = n ? sum / double(n) : 0.0;
}

}  // namespace

SurfaceDistance surface_distance(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                                 Progress* progress) {
  SurfaceDistance out;
  if (progress) progress->report(0.0, "surface distance");
  const ClosestPointTree tree_a(VA, FA);
  if (progress) progress->report(0.1, "surface distance");
  const ClosestPointTree tree_b(VB, FB);
  one_side(VA, FA, tree_b, &out.a_to_b, &out.mean_a_to_b, progress, 0.2, 0.6);
  one_side(VB, FB, tree_a, &out.b_to_a, &out.mean_b_to_a, progress, 0.6, 1.0);
  if (progress) progress->report(1.0, "surface distance");
  return out;
}

}  // namespace paramorph
