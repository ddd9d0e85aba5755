// The arrangement of two sphere maps (thesis 4.4; DESIGN.md §4.4 step 3): the
// great-circle arcs of map A's edges and of map B's edges cut the sphere into
// cells, each the intersection of one face of A with one face of B, convex,
// bounded by pieces of the two faces' edges.
//
// Built by walking from cell to cell: one vertex of B is located in A
// (point_location.h), and from its cell the walk crosses every cell side,
// a side on an edge of A leading to the next face of A, one on an edge of B to
// the next face of B. Each cell is found from the 18 orientation tests
// between the corners of its two faces and the other face's edges (vertex
// inside, arcs crossing, entry or exit), so the work is O(1) per cell and
// O(E + K) in all (K crossings). Every test is perturbed_orientation() of
// input points (sphere_predicates.h): map B is moved infinitesimally, so no
// vertex lies on an edge of the other map, no two arcs overlap and no three
// meet, and all cells fit together exactly. A crossing is named by its pair of
// edges, so the four cells around it share one vertex.
//
// Degenerate inputs therefore give exact but tiny features here (a vertex of
// B on a vertex of A becomes a vertex near a cluster of crossings, a shared
// edge a zero-width strip); merge_close_vertices() removes them.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

/// One fold-free sphere map, with the topology the walk steps through.
struct SphereMapTopology {
  MatrixX3d X;           ///< #V by 3 unit vectors
  MatrixX3i F;           ///< #F by 3, counter-clockwise seen from outside (det > 0)
  MatrixX3i neighbors;   ///< #F by 3: the face across the edge opposite each corner
  MatrixX3i face_edges;  ///< #F by 3: the edge opposite each corner (index into edges)
  MatrixX2i edges;       ///< #E by 2 vertex pairs (a < b)
};

/// Vertices of the arrangement are numbered: A's vertices 0 .. num_a - 1,
/// B's vertices num_a .. num_a + num_b - 1, then the crossings in the order
/// they were found.
struct SphereArrangement {
  Index num_a = 0, num_b = 0;
  std::vector<Index> crossing_edge_a;  ///< per crossing: the edge of A
  std::vector<Index> crossing_edge_b;  ///< per crossing: the edge of B
  /// Per crossing: unit vector on B's arc (|s1| q0 + |s0| q1 normalised, s_i
  /// the determinant of A's edge with q_i), so it lies on B's arc by
  /// construction and within rounding of A's great circle even where the
  /// two arcs are nearly parallel; only its place along them is uncertain then.
  std::vector<Eigen::Vector3d> crossing_position;
  std::vector<Index> cell_face_a, cell_face_b;  ///< per cell, its face of A and of B
  std::vector<Index> cell_start;                ///< #cells + 1 offsets into corner and side
  std::vector<Index> corner;  ///< per cell its polygon (vertex ids), counter-clockwise
  /// side[k]: the edge the cell side from corner[k] to the next corner lies on:
  /// an edge e of A as e, an edge e of B as -1 - e.
  std::vector<Index> side;
  VectorXi face_b_of_a;  ///< #VA: the face of B holding each vertex of A
  VectorXi face_a_of_b;  ///< #VB: the face of A holding each vertex of B

  Index num_cells() const { return Index(cell_face_a.size()); }
  Index num_crossings() const { return Index(crossing_edge_a.size()); }
  Index num_vertices() const { return num_a + num_b + num_crossings(); }
};

/// a, b: two fold-free sphere maps, each covering the sphere once (checked by
/// the caller, spherical_overlay.cpp). Raises Cancelled through `progress`.
/// Throws std::logic_error if a cell does not close, which the consistency of
/// the perturbed predicates rules out.
SphereArrangement arrange_sphere_maps(const SphereMapTopology& a, const SphereMapTopology& b,
                                      ProgressWindow progress = {});

}  // namespace paramorph::morph
