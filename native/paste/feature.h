// A feature cut from a surface, free of where it came from (thesis 5.2;
// DESIGN.md §4.5 step 1; the lead's paste design): its mesh, its fold-free
// map pinned to the base's map, the base surface under it, and the offset of
// the feature from its base as a vector displacement map in the base's local
// frame. Plain Eigen arrays, so the add-on can store it (Python:
// Feature.to_arrays() / Feature.from_arrays()).
//
// FEATURE FRAME: origin = the base surface's point at uv = 0 (the area
// centroid of the base map), axes e_u, e_v, n = the base's frame there
// (paste/map_frames.h: e_u along increasing u, n the outside normal,
// n = e_u × e_v). Every position below is in that frame: x_frame =
// axesᵀ (x_source - origin), and back: x_source = origin + axes x_frame.
//
// DISPLACEMENT GRID: resolution² NODES over the square [-radius, radius]²
// centred at uv = 0 (it holds the whole domain: |uv| is largest on the
// boundary). Node (i, j) (row i along v, column j along u) sits at
//   uv = grid_origin + grid_spacing · (j, i),
//   grid_origin = (-radius, -radius), grid_spacing = 2 radius / (resolution - 1),
// and is row i · resolution + j of `displacement` and `mask`. At a node
// inside the map's domain (mask 1):
//   displacement = frame(g)ᵀ (P(g) - B(g)),
// P(g) the feature at g (through the feature map), B(g) the base at g
// (through the base map), frame(g) the base's local frame at B(g); components
// (along e_u, along e_v, along n). Nodes outside the domain but within one
// cell diagonal of it (mask 0) hold the value at the domain's closest point,
// so a bilinear lookup anywhere in the domain reads defined values; nodes
// farther out hold 0.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/types.h"

namespace paramorph::paste {

/// Largest displacement grid side: 2048^2 nodes hold 100 MB of displacements;
/// far more than any feature's detail needs, and the allocation of a much
/// larger one (65536: 100 GB) crashed the process.
constexpr int kMaxFeatureResolution = 2048;

struct Feature {
  MatrixX3i F;              ///< #Fs by 3 faces (local vertex indices, source orientation)
  MatrixX3d V;              ///< #Vs by 3 feature positions, feature frame
  MatrixX2d uv;             ///< #Vs by 2 feature map (fold-free; boundary = base_uv's exactly; = base_uv if carried)
  MatrixX3d base_V;         ///< #Vs by 3 base surface positions, feature frame (same faces F)
  MatrixX2d base_uv;        ///< #Vs by 2 base map (fold-free, area centroid at 0)
  /// Boundary loops in local indices, each ordered the way its faces
  /// traverse it (1 for a disc, 2 for an annulus).
  std::vector<std::vector<Index>> boundary_loops;
  VectorXi source_faces;    ///< #Fs: the selected source face of each local face
  VectorXi source_vertices; ///< #Vs: the source vertex of each local vertex

  Eigen::Vector3d origin = Eigen::Vector3d::Zero();     ///< frame origin, source coordinates
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();   ///< columns e_u, e_v, n, source coordinates

  /// Carried as its own mesh (a long protrusion: a trunk, a horn with its
  /// root, a limb). Its map cannot be both fold-free and pinned to the base
  /// map's boundary (a tube closed at its tip, pinned to a circle), so `uv`
  /// is the base map itself (base_uv: fold-free, the same boundary) and
  /// PasteFit::KeepForm pastes the feature's own triangles, placed rigidly and
  /// sewn into a hole cut in the target, instead of resampling it on the
  /// target's refined faces (where its tip would be squeezed out of reach).
  bool carried = false;

  double radius = 0;            ///< max |uv| over the boundary
  double area = 0;              ///< 3D area of the feature
  double mean_edge_length = 0;  ///< of the feature

  int resolution = 0;                               ///< grid nodes per side
  Eigen::Vector2d grid_origin = Eigen::Vector2d::Zero();  ///< uv of node (0, 0)
  double grid_spacing = 0;                          ///< uv distance between nodes
  MatrixX3d displacement;   ///< resolution² by 3, row i · resolution + j (see above)
  VectorXi mask;            ///< resolution²: 1 where the node is inside the domain
};

}  // namespace paramorph::paste
