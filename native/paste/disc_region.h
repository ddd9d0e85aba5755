// The target's region under a pasted feature, grown as a topological disc
// (DESIGN.md §4.5; thesis 5.2: the base surface under the feature must have a
// planar parameterization, and a fold-free one exists for a disc).
//
// Faces are added one at a time from the anchor's face outwards, in order of
// their edge-path distance from the anchor (Dijkstra's distance of their
// nearest corner), and only where the region stays a disc: a face that
// shares one edge with the region and brings a new vertex, or two edges (it
// fills a notch). A face that would touch the region at a vertex only, close
// a loop around a hole or a handle, or close the surface is put off until a
// neighbour joins. Every face with a corner nearer than `grow` is added
// where it can be, so the region's cut runs beyond `grow`; farther faces
// only while a face within `cover` (all its corners nearer) is still
// missing, never one beyond `limit`.
//
// When a face within `cover` is still missing at the end, the surface there
// is not a disc: a handle or a hole (a second boundary) lies under the
// feature or the surface wraps around a part thinner than the feature. A
// disc grown this way is a disc by construction (Euler characteristic 1, one
// boundary loop, manifold), so the fold-free map of paste/disc_map.h applies.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::paste {

struct DiscRegion {
  std::vector<Index> faces;     ///< the disc's faces, in the order they were added (the anchor face first)
  std::vector<Index> vertices;  ///< their vertices, each once, in the order they joined
  std::vector<char> in_disc;    ///< #F: 1 for the disc's faces
  /// The disc's vertices on an edge it shares with a face outside it (its
  /// cut, not the target's own boundary): where the map around the anchor ends.
  std::vector<Index> cut_vertices;
  std::vector<double> distance;  ///< #V: edge-path distance from the anchor; +inf beyond `limit`
};

/// mesh: manifold (edge_faces() of size 1 or 2). anchor_face, anchor: the
/// face holding the anchor point and the point. 0 < cover <= grow <= limit,
/// path distances in the mesh's units. Throws TargetTooSmallError (with a
/// message an artist can act on) when a face within `cover` cannot join.
DiscRegion grow_disc_region(const TriMesh& mesh, Index anchor_face, const Eigen::Vector3d& anchor, double cover,
                            double grow, double limit);

/// Whether `faces` (distinct indices into mesh.F(); mesh manifold) form a
/// disc once the target's own holes inside them are closed: connected along
/// one loop of cut edges (edges shared with a face outside), every other
/// boundary loop made of the target's open edges only, no vertex where the
/// boundary touches itself, and Euler characteristic V - E + F = 1 - (the
/// number of such holes). False for a handle, for a region that wraps around
/// a thin part (two cut loops), for a bow-tie.
bool is_disc_up_to_holes(const TriMesh& mesh, const std::vector<Index>& faces);

}  // namespace paramorph::paste
