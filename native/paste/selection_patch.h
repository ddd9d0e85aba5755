// The user's face selection checked and cut out as its own mesh (thesis 5.2:
// "the user selects the feature faces"; DESIGN.md §4.5 step 1). Cut-and-paste
// takes a feature that is one edge-connected disc (a bump, a boss, an ear) or
// one annulus (a ring-shaped rib); anything else is a typed error naming what
// is wrong, so the add-on can tell the artist.
#pragma once

#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::paste {

struct SelectionPatch {
  MatrixX3i F;         ///< #Fs by 3: the selected faces in local vertex indices (source orientation)
  VectorXi faces;      ///< #Fs: source face of each local face (ascending)
  VectorXi vertices;   ///< #Vs: source vertex of each local vertex (ascending)
  /// Boundary loops of the selection in local indices, ordered the way its
  /// faces traverse them (1 for a disc, 2 for an annulus).
  std::vector<std::vector<Index>> boundary_loops;
  /// Source faces not selected that share a vertex with the selection's
  /// boundary: the one ring just outside it (ascending).
  VectorXi ring_faces;
};

/// mesh: the source mesh (a manifold, checked by the caller); selected: face
/// indices of the feature, in any order.
/// Throws InvalidInputError for an index out of [0, #F) or repeated,
/// EmptySelectionError for no face, WholeMeshSelectedError for every face, and
/// SelectionTopologyError unless the selection is one edge-connected piece
/// that is a disc (1 boundary loop, Euler characteristic 1) or an annulus
/// (2 loops, Euler characteristic 0); its message says "is not connected",
/// "has handles", "has N boundary loops" or "is pinched at vertices ...".
SelectionPatch selection_patch(const TriMesh& mesh, const std::vector<Index>& selected);

}  // namespace paramorph::paste
