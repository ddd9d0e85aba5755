// TriMesh: a triangle mesh with explicit topology, computed once on demand and
// shared by every algorithm (DESIGN.md §6, in the manner of geometry-central).
//
// Topology is built from the face list alone and tolerates broken input
// (non-manifold edges, isolated vertices): validation reads it to report what
// is wrong. Algorithms that need a manifold call validate() first.
//
// All of it is built together on the first call to any getter (O(F) plus a
// sort of each vertex's few edges; about 0.25 s for 1.3M faces on one core), under
// std::call_once, so concurrent first calls from several threads are safe.
// Copies of a TriMesh share the built topology.
#pragma once

#include <memory>
#include <vector>

#include "mesh/types.h"

namespace paramorph {

/// Compressed rows: the items of row r are items[offsets[r] .. offsets[r+1]).
struct Csr {
  std::vector<Index> offsets;
  std::vector<Index> items;
  Index rows() const { return offsets.empty() ? 0 : Index(offsets.size()) - 1; }
  Index begin(Index r) const { return offsets[r]; }
  Index end(Index r) const { return offsets[r + 1]; }
  Index size(Index r) const { return offsets[r + 1] - offsets[r]; }
};

class TriMesh {
 public:
  /// V: #V by 3 positions; F: #F by 3 indices. Indices must be in [0, #V)
  /// (checked by validate_arrays, not here).
  TriMesh(MatrixX3d V, MatrixX3i F);

  const MatrixX3d& V() const { return V_; }
  const MatrixX3i& F() const { return F_; }
  Index num_vertices() const { return Index(V_.rows()); }
  Index num_faces() const { return Index(F_.rows()); }

  /// #E by 2 undirected edges (a < b), sorted lexicographically. A face that
  /// repeats an index contributes a self-edge (a == a), kept so face_edges()
  /// stays total; it is never anyone's neighbour.
  const MatrixX2i& edges() const;
  /// #F by 3: edge index of the edge opposite corner k of face f
  /// (the edge between F(f,(k+1)%3) and F(f,(k+2)%3)).
  const MatrixX3i& face_edges() const;
  /// Per edge, the faces that contain it, ascending (1 on a boundary, 2 inside,
  /// more if non-manifold).
  const Csr& edge_faces() const;
  /// Per vertex, the faces that contain it, as (face * 3 + corner) entries, ascending.
  const Csr& vertex_corners() const;
  /// Per vertex, its neighbouring vertices (sorted ascending) — the 1-ring.
  const Csr& vertex_neighbors() const;
  /// Per vertex, the edge index of each entry of vertex_neighbors() (same order).
  const Csr& vertex_neighbor_edges() const;
  /// Boundary loops as ordered vertex cycles (only edges with exactly one face),
  /// each running the way its faces traverse it and starting at its lowest
  /// vertex. Loops are followed fan by fan around each vertex, so two holes
  /// touching at one vertex stay two loops; where fans are broken (flipped
  /// faces, non-manifold edges) a loop may come out as an open chain, and the
  /// walk always ends (each boundary half-edge is used once).
  const std::vector<std::vector<Index>>& boundary_loops() const;
  /// Connected components: per-vertex label in [0, num_components); isolated
  /// vertices (in no face) get their own label.
  const VectorXi& vertex_component() const;
  Index num_components() const;

  struct Cache;  ///< lazily built topology (implementation detail, tri_mesh.cpp)

 private:
  MatrixX3d V_;
  MatrixX3i F_;
  std::shared_ptr<Cache> cache_;
};

}  // namespace paramorph
