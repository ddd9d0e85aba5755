// Point location in a planar map (thesis 5.2: the feature is looked up
// through its parameterization): which face of a fold-free map holds a uv
// point, and where. The map's triangles are embedded at z = 0 in CGAL's AABB
// tree (mesh/closest_points.h), so a point outside the map's domain gets the
// domain's closest point, which the displacement grid uses to extend its
// values one cell past the boundary.
#pragma once

#include "mesh/closest_points.h"

namespace paramorph::paste {

struct MapLocation {
  VectorXi face;      ///< #Q: face holding the point (or its closest domain point)
  MatrixX3d bary;     ///< #Q by 3: barycentric coordinates there (>= 0, sum 1)
  VectorXd distance;  ///< #Q: 0 (up to round-off) inside the domain, else the distance to it
};

/// Solver object: built once per map, queried many times.
class MapLocator {
 public:
  /// uv: #V by 2 fold-free map; F: #F by 3 faces.
  MapLocator(const MatrixX2d& uv, const MatrixX3i& F);
  /// Q: #Q by 2 uv points.
  MapLocation locate(const MatrixX2d& Q) const;

 private:
  ClosestPointTree tree_;
};

/// X at the located points: Σ_k bary(q, k) X(F(face(q), k)), #Q by X.cols().
Eigen::MatrixXd interpolate(const MatrixX3i& F, const MapLocation& at, const Eigen::MatrixXd& X);

}  // namespace paramorph::paste
