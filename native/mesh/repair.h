// repair(): turns the meshes artists bring (unwelded seams, duplicate or
// degenerate faces, inside-out or inconsistently wound parts, non-manifold
// vertices and edges, holes, loose parts) into a clean manifold triangle mesh,
// with a map back to the input and a report of every change (issue 19).
// The geometry work is CGAL's polygon-mesh processing: orient_polygon_soup
// (consistent orientation, non-manifold splits), remove_degenerate_faces,
// triangulate_refine_and_fair_hole (Liepa's hole filling with fairing).
#pragma once

#include <string>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph {

struct RepairOptions {
  /// Vertices closer than this times the bounding-box diagonal are welded
  /// (0: exactly equal positions only).
  double weld_tolerance = 1e-6;
  bool fill_holes = true;
  /// Reverse every part whose faces enclose a negative volume.
  bool orient_outward = true;
  /// Keep only the part with the largest area (the others are reported).
  bool keep_largest_component = false;
};

/// Every change repair() made, in counts (input faces and vertices).
struct RepairReport {
  Index welded_vertices = 0;           ///< input vertices merged into another one
  Index degenerate_faces_removed = 0;  ///< faces naming a vertex twice (after welding) or of zero area
  Index duplicate_faces_removed = 0;   ///< faces on the same three vertices as an earlier one
  Index isolated_vertices_removed = 0; ///< vertices in no face
  Index faces_reversed = 0;            ///< faces whose winding was turned (consistency or outward)
  Index parts_turned_outward = 0;      ///< parts that were inside out
  Index non_manifold_vertices_split = 0;  ///< vertices given one copy per fan of faces
  Index non_manifold_edges = 0;        ///< edges with more than two faces (cut apart)
  Index holes_filled = 0;
  Index holes_not_filled = 0;          ///< holes CGAL could not triangulate (left open)
  Index single_faces_left_open = 0;    ///< parts of one triangle (closing one would make a two-sided pillow)
  Index fill_faces_added = 0;
  Index fill_vertices_added = 0;
  Index fairing_failed = 0;            ///< holes filled but left unfaired (the fairing solve failed)
  Index components = 0;                ///< parts in the result
  Index components_removed = 0;        ///< parts dropped by keep_largest_component
  Index faces_removed_with_components = 0;
  /// Plain-word sentences, one per kind of change ("welded 12 vertices ...").
  std::vector<std::string> changes() const;
  bool changed() const { return !changes().empty(); }
};

struct RepairResult {
  MatrixX3d V;               ///< repaired positions (input positions kept; fill vertices added)
  MatrixX3i F;               ///< repaired faces, consistently oriented
  VectorXi vertex_source;    ///< #V: the input vertex of each vertex, -1 for a fill vertex
  VectorXi face_source;      ///< #F: the input face of each face, -1 for a fill face
  VectorXi input_vertex_target;  ///< #V_in: where each input vertex went, -1 when dropped
  RepairReport report;
};

/// V: #V by 3 positions; F: #F by 3 indices (checked: validate_arrays, at
/// least one face). Never changes a kept vertex's position: welded vertices
/// take the position of the lowest-numbered one. Throws InvalidInputError on
/// bad options, ComputeError when the pieces cannot be made manifold.
RepairResult repair(const MatrixX3d& V, const MatrixX3i& F, const RepairOptions& options = {},
                    Progress* progress = nullptr);

}  // namespace paramorph
