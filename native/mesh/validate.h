// Mesh validation (DESIGN.md §3): what is wrong with an input mesh, and where.
#pragma once

#include <string>
#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph {

/// Everything validate() finds. Index lists are 0-based and sorted.
struct MeshReport {
  Index vertices = 0;
  Index faces = 0;
  Index edges = 0;
  Index components = 0;       ///< connected components, each isolated vertex counting as one
  Index boundary_loops = 0;
  Index boundary_edges = 0;   ///< edges with exactly one face
  Index euler_characteristic = 0;  ///< V - E + F over all vertices
  /// Genus from chi = 2 - 2g - b of the one surface (isolated vertices left
  /// out of chi); -1 when undefined (several surfaces, non-manifold, or a
  /// non-orientable count).
  Index genus = -1;
  std::vector<Index> non_manifold_edges;     ///< edge indices with > 2 faces
  MatrixX2i non_manifold_edge_vertices;      ///< #non_manifold_edges by 2: their (a < b) vertices
  std::vector<Index> non_manifold_vertices;  ///< vertices whose faces form several fans
  std::vector<Index> degenerate_faces;       ///< repeated indices or area <= tolerance
  std::vector<Index> repeated_vertex_faces;  ///< faces naming one vertex twice (also degenerate)
  std::vector<Index> duplicate_faces;        ///< faces on the same three vertices as an earlier face
  std::vector<Index> isolated_vertices;      ///< vertices in no face
  std::vector<Index> inconsistent_orientation_edges;  ///< interior edges used twice in one direction
  MatrixX2i inconsistent_orientation_edge_vertices;   ///< their (a < b) vertices, one row each
  bool is_closed_genus0 = false;
};

/// Checks raw arrays before any topology is built: shapes, finite coordinates
/// small and large enough that face areas neither overflow nor underflow,
/// index range. Throws InvalidInputError naming the first offending entries.
void validate_arrays(const MatrixX3d& V, const MatrixX3i& F);

/// Full report. Never throws for a well-formed array pair (call validate_arrays
/// first). A face is degenerate when two indices repeat or its area is below
/// `relative_area_tolerance` times the squared bounding-box diagonal.
MeshReport validate(const TriMesh& mesh, double relative_area_tolerance = 1e-14);

/// Throws the matching MeshError subclass unless the mesh is a closed,
/// Throws NonManifoldError unless every edge has at most two faces, the faces
/// around every vertex form one fan and neighbouring faces agree on their
/// orientation; the message names the offending vertices and edges (as
/// vertex pairs) and says how to fix them in Blender. Open or closed, any
/// genus: what every algorithm that walks the surface needs.
void require_manifold(const MeshReport& report);

/// connected, manifold, consistently oriented genus-0 surface without
/// degenerate faces or isolated vertices. Checks in this order: non-manifold,
/// degenerate, several surfaces, not closed (says how many boundary loops),
/// loose vertices (DisconnectedError), orientation (NonManifoldError: not an
/// oriented manifold), not genus 0 (says the genus). Messages name vertices,
/// edges as vertex pairs, and faces, so an artist can select them.
void require_closed_genus0(const MeshReport& report);

/// Short human-readable list "0, 5, 17 (and 3 more)" for error messages.
std::string format_indices(const std::vector<Index>& indices, std::size_t max_shown = 10);

/// Edges as vertex pairs "(3, 7), (8, 12) (and 2 more)": rows of a #k by 2 matrix.
std::string format_vertex_pairs(const MatrixX2i& pairs, std::size_t max_shown = 10);

}  // namespace paramorph
