// Half-edge collapses that take a closed genus-0 mesh down to a tetrahedron,
// recorded so they can be undone one at a time (Hoppe 1996, progressive
// meshes). Undone in reverse order, they put the vertices back one by one,
// each into a mesh that is a whole closed surface:
// param/spherical/progressive_sphere_map embeds the mesh on the sphere that
// way, valid at every insertion (Praun & Hoppe 2003).
//
// Order: the quadric error of the removed vertex at the kept vertex's place
// (Garland & Heckbert 1997, restricted to half-edge collapses, so every level
// is made of input vertices at their input positions), with the edge length
// to order collapses on flat parts. A collapse that would turn a face over
// in 3D waits; at the end every collapse the topology allows is taken, so the
// sequence always reaches the tetrahedron. Topology: an edge collapses only
// when its ends share exactly the two neighbours across it (the link
// condition), which keeps every level a closed manifold sphere; every
// triangulated sphere but the tetrahedron has such an edge (Steinitz).
//
// Why not mesh/simplify (CGAL's edge_collapse): it moves the kept vertex
// (levels would not be input vertices), does not report the removed vertex's
// ring, and takes a 100k-face mesh down to 4 faces in 1.3-2.5 s, most of the
// sphere map's budget; this takes about 0.1 s.
#pragma once

#include <array>
#include <vector>

#include "common/progress.h"
#include "mesh/tri_mesh.h"

namespace paramorph {

struct CollapseSequence {
  /// Per collapse, in the order they were applied: the vertex removed and the
  /// neighbour it was merged into.
  std::vector<Index> removed, kept;
  /// Per collapse c, the removed vertex's faces just before it (input face
  /// ids), counter-clockwise around it, starting with the face across the
  /// collapsed edge from which the ring continues: faces.items[faces.begin(c) + k]
  /// had the corners (removed, ring[k], ring[k + 1]) then, where ring =
  /// rings.items[rings.begin(c) ...] starts with kept. Its first and last
  /// faces are the two the collapse removes.
  Csr faces, rings;
  /// The four vertices left (the tetrahedron) and its four faces (input face
  /// ids, whose corners are then the four vertices).
  std::array<Index, 4> base_vertices{};
  std::array<Index, 4> base_faces{};
  Index geometric_refusals = 0;  ///< collapses taken only in the last, topology-only pass
};

/// mesh: closed, connected, manifold, genus 0 (validate first). progress:
/// 0..1 over the collapses; Cancelled through it.
CollapseSequence collapse_sequence(const TriMesh& mesh, ProgressWindow progress = {});

/// Replays collapses [0, count) of `sequence` on faces (in place: F, the
/// input faces): a kept vertex takes the removed one's place in its faces,
/// and the two faces across each collapsed edge are marked dead (alive[f] =
/// 0, their corners left as they were). undo_collapse reverses one.
void apply_collapse(const CollapseSequence& sequence, Index c, MatrixX3i& F, std::vector<char>& alive);
void undo_collapse(const CollapseSequence& sequence, Index c, MatrixX3i& F, std::vector<char>& alive);

}  // namespace paramorph
