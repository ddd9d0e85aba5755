// Spherical overlay of two sphere maps into one merged topology (thesis 4.4;
// DESIGN.md §4.4 step 3): the great-circle arcs of map A's edges are
// intersected with those of map B by walking from face to face (O(E + K)),
// every sign test an exact orientation predicate (CGAL) with ties broken by
// symbolic perturbation; the cells (face of A ∩ face of B, convex) are
// triangulated into one closed genus-0 mesh covering the sphere once, and each
// merged vertex is located in a face of A and of B with barycentric
// coordinates, which gives its position on both models.
//
// Steps: sphere_arrangement.h (the exact, perturbed arrangement),
// merge_close_vertices.h (vertices within merge_tolerance of one point become
// one vertex: coincident vertices, vertices on the other map's edges,
// overlapping edges), triangulate_spherical_polygon.h (each cell, positive
// triangles only), then the barycentric coordinates here.
#pragma once

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

struct OverlayOptions {
  /// Angular distance (radians) under which two vertices of the overlay are
  /// the same point. A vertex of B this close to a vertex of A becomes one
  /// merged vertex of both (vertex_kind 2, placed on A's vertex); a vertex
  /// this close to an arc of the other map lies on that arc (the crossings
  /// next to it are merged into it); two arcs this close to each other along a
  /// stretch share their merged edges there. Every merged vertex stays within
  /// this distance of the input vertices and of the input arcs it stands for
  /// (but see OverlayStats::max_merge_distance), so no triangle thinner than
  /// this is made where the inputs have none (the guarantee: see overlay()).
  /// Vertices of one map are never merged with each other. Values below
  /// 1e-15 act as 1e-15 (rounding of the distance computations).
  ///
  /// Why 1e-6: features finer than that are not worth keeping in a morph. The
  /// aligned map B brings paired feature points to A's only within its
  /// solver's accuracy (~1e-8 rad), and a pair left a little over the
  /// tolerance apart makes a cluster of crossings with triangles of that size
  /// (148 of them on the known-truth pair at 1e-9); triangles of 1e-7 of the
  /// model's size are below float32 resolution in Blender and degenerate by
  /// validate()'s relative area test (1e-14 of the squared diagonal). The
  /// morph's 3D positions stay on both surfaces whatever the tolerance: each
  /// merged vertex is placed on the vertex, edge or face of each input that
  /// the merging assigns it (so moving it on the sphere slides it along them).
  double merge_tolerance = 1e-6;
};

/// What the overlay did and how long each step took.
struct OverlayStats {
  double merge_tolerance = 0;  ///< the tolerance used (see OverlayOptions::merge_tolerance)
  Index cells = 0;             ///< cells of the exact arrangement (face of A ∩ face of B)
  Index crossings = 0;         ///< arc crossings of the exact arrangement
  Index merged_vertices = 0;   ///< arrangement vertices merged into another
  /// Largest distance (radians) from a merged vertex to the input vertices and
  /// arcs it stands for: <= merge_tolerance, except where a tiny cell that
  /// merging turned over was repaired by merging two of its vertices (at most
  /// 16 merge_tolerance apart), which happens only in inputs that nearly
  /// coincide at about the tolerance's scale.
  double max_merge_distance = 0;
  Index degenerate_cells = 0;  ///< cell pieces with no positive triangulation (always 0: checked)
  Index folded = 0;            ///< merged triangles with det <= 0, exact (always 0: checked)
  Index open_edges = 0;        ///< merged half-edges without one opposite twin (always 0: checked)
  /// Smallest altitude (radians, as a chord: twice the flat area over the
  /// longest side) of the merged triangles on the sphere.
  double min_altitude = 0;
  /// Merged triangles with an altitude under kMinAltitudeInTolerances times
  /// merge_tolerance on the sphere, left after the repair (see overlay()).
  Index thin_triangles = 0;
  double seconds_validate = 0, seconds_arrangement = 0, seconds_merge = 0, seconds_triangulate = 0,
         seconds_attributes = 0, seconds = 0;
};

struct MergedTopology {
  MatrixX3d V;      ///< #M by 3 merged vertices on the unit sphere
  MatrixX3i F;      ///< #K by 3 merged triangles, det > 0 (the inputs' orientation),
                    ///< a closed genus-0 manifold covering the sphere once
  VectorXi face_a;  ///< #M: a face of A holding each merged vertex
  /// #M by 3: barycentric coordinates of each merged vertex in face_a, by
  /// central projection (where the ray through V meets the flat triangle of
  /// sphere_a's corners): 1 at the corner for a vertex of A, 0 opposite the
  /// edge for a point on an edge of A (the same weights from both faces of the
  /// edge, so positions interpolated from A are continuous).
  MatrixX3d bary_a;
  VectorXi face_b;  ///< #M: the same for B
  MatrixX3d bary_b;
  VectorXi source_face_a;  ///< #K: the face of A each merged triangle lies in
  VectorXi source_face_b;  ///< #K: the face of B each merged triangle lies in
  /// #K by 9: per merged triangle and corner (3 values each) the barycentric
  /// coordinates of that corner in source_face_a (they differ from bary_a
  /// where a vertex sits on an edge or a vertex of A: then they are its
  /// coordinates in this face). corner_bary_b the same for B.
  Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor> corner_bary_a, corner_bary_b;
  /// #M: 0 a vertex of A, 1 a vertex of B, 2 a vertex of both (within
  /// merge_tolerance), 3 a crossing of an edge of A with an edge of B.
  VectorXi vertex_kind;
  /// #VA: the merged vertex of each vertex of A (A's vertices come first, so
  /// vertex_of_a[i] == i); #VB: the same for B. Every input vertex is one
  /// merged vertex.
  VectorXi vertex_of_a, vertex_of_b;
  OverlayStats stats;
};

/// The slivers guarantee, in tolerances: a merged triangle thinner than this
/// times the tolerance used (OverlayStats::merge_tolerance) on the sphere is a
/// sliver, which the overlay removes by merging two of its corners.
constexpr double kMinAltitudeInTolerances = 0.5;

/// InvalidInputError for options overlay() would refuse (so a caller can
/// refuse them before its own long work).
void check_overlay_options(const OverlayOptions& options);

/// sphere_a: #VA by 3 unit vectors (|v| within 1e-9 of 1, renormalised);
/// FA: #FA by 3 faces of a closed genus-0 mesh, every face positively
/// oriented (det(a, b, c) > 0, exact), the map covering the sphere once. The
/// same for sphere_b, FB. Raises InvalidInputError (wrong shapes, indices,
/// non-unit points, folded faces: their count and indices, a map covering the
/// sphere more than once), the MeshError subclasses of the mesh checks (not
/// closed, not genus 0, non-manifold, degenerate), Cancelled through
/// `progress`. The result is checked before it is returned (every triangle
/// det > 0 exactly, every half-edge with one twin); where the two maps nearly
/// coincide at a scale their own thinnest faces make unresolvable in double
/// precision (faces squeezed to ~1e-12 and a copy turned by ~1e-12) that
/// check fails and InvalidInputError says so instead of returning a broken mesh.
///
/// No slivers: every merged triangle whose altitude on the sphere (twice its
/// flat area over its longest side) is under kMinAltitudeInTolerances times
/// the tolerance used (a tiny cell between features just over the tolerance
/// apart, or a needle along two nearly parallel arcs) has its two closest
/// corners merged (at most 2 tolerances apart, where may_merge() allows), and
/// the cells are triangulated again. Guarantee: stats.thin_triangles counts
/// what is left and stats.min_altitude the thinnest triangle. It is 0 in
/// every near-degenerate case the tests build (a vertex 1e-10..3e-6 off an
/// arc or a vertex of the other map, a copy turned by 1e-10..1e-3, the
/// known-truth morph); it is not proven 0: a sliver none of whose corner
/// pairs may be merged (two crossings on different edges of one map, say
/// inside a face of that map with a very sharp corner) is counted, not
/// removed. A repair moves vertices by a few tolerances at most
/// (stats.max_merge_distance, under 2 in the tests; 16 bounds all repairs).
MergedTopology overlay(const MatrixX3d& sphere_a, const MatrixX3i& FA, const MatrixX3d& sphere_b,
                       const MatrixX3i& FB, const OverlayOptions& options = {},
                       Progress* progress = nullptr);

/// Area of the spherical triangle (a, b, c) of unit vectors, signed like
/// det(a, b, c) (Van Oosterom & Strackee 1983).
double spherical_triangle_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c);

}  // namespace paramorph::morph
